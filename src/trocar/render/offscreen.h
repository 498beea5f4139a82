#pragma once
/// Headless OpenGL: a surfaceless EGL context (Mesa's EGL_PLATFORM_SURFACELESS_MESA works with no
/// display and no /dev/dri; llvmpipe renders) and a framebuffer object to draw into and read back.
#include <cstdint>
#include <memory>
#include <vector>

namespace trocar {

/// An RGB image, rows top to bottom.
struct Image {
  int width = 0;                      ///< pixels
  int height = 0;                     ///< pixels
  std::vector<std::uint8_t> rgb;      ///< 3 bytes per pixel
  const std::uint8_t* at(int x, int y) const { return &rgb[3 * (std::size_t(y) * std::size_t(width) + std::size_t(x))]; }
};

/// An OpenGL 3.3 core context with no window, current on the creating thread, and a
/// width × height framebuffer (multisampled when samples > 1, resolved on read).
class OffscreenContext {
 public:
  /// Throws trocar::Error saying which EGL or GL step failed (e.g. no EGL platform).
  OffscreenContext(int width, int height, int samples = 4);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  /// Binds the framebuffer for drawing.
  void bind();
  /// Reads the drawn frame (resolving multisampling) into `out`.
  void read(Image& out);
  int width() const { return width_; }    ///< pixels
  int height() const { return height_; }  ///< pixels
  /// GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6".
  const char* description() const;

 private:
  struct Egl;
  std::unique_ptr<Egl> egl_;
  int width_ = 0;
  int height_ = 0;
  int samples_ = 1;
};

/// Keeps the calling thread — and the threads Mesa's llvmpipe starts from it, which inherit its
/// CPU mask — off `cpu` (the haptic thread's), and sets LP_NUM_THREADS to the CPUs left unless the
/// user set it. Call before creating a GL context. No effect on a single-CPU machine.
void keep_rendering_off_cpu(int cpu);

/// Writes an image as PNG (libpng). Throws trocar::Error naming the file on failure.
void write_png(const char* path, const Image& image);
/// Reads a PNG of any colour type as RGB (libpng's simplified API). Throws trocar::Error naming
/// the file and libpng's reason.
Image read_png(const char* path);

}  // namespace trocar
