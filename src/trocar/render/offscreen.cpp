#include "trocar/render/offscreen.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <malloc.h>
#include <png.h>

#include <pthread.h>
#include <sched.h>

#include <cstdio>
#include <cstdlib>
#include <thread>
#include <string>

#include "trocar/core/error.h"

namespace trocar {

struct OffscreenContext::Egl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  GLuint draw_fbo = 0, draw_color = 0, draw_depth = 0;
  GLuint resolve_fbo = 0, resolve_color = 0;
  std::string description;
  std::vector<std::uint8_t> rgba;
};

OffscreenContext::OffscreenContext(int width, int height, int samples)
    : egl_(std::make_unique<Egl>()), width_(width), height_(height), samples_(samples < 1 ? 1 : samples) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw Error("render: frame size " + std::to_string(width) + "x" + std::to_string(height) + " out of range");
  Egl& e = *egl_;
  if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless"))
    throw Error("render: EGL has no surfaceless platform (EGL_MESA_platform_surfaceless); install libegl-mesa0");
  e.display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (e.display == EGL_NO_DISPLAY) throw Error("render: eglGetPlatformDisplayEXT(surfaceless) failed");
  EGLint major = 0, minor = 0;
  if (!eglInitialize(e.display, &major, &minor)) throw Error("render: eglInitialize failed");
  if (!eglBindAPI(EGL_OPENGL_API)) throw Error("render: eglBindAPI(OpenGL) failed");
  const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  // Surfaceless: any config will do, there is no surface to match.
  eglChooseConfig(e.display, config_attributes, &config, 1, &count);
  const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                       EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  e.context = eglCreateContext(e.display, count > 0 ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, context_attributes);
  if (e.context == EGL_NO_CONTEXT) throw Error("render: eglCreateContext(OpenGL 3.3 core) failed");
  if (!eglMakeCurrent(e.display, EGL_NO_SURFACE, EGL_NO_SURFACE, e.context))
    throw Error("render: eglMakeCurrent(no surface) failed");
  e.description = std::string(reinterpret_cast<const char*>(glGetString(GL_RENDERER))) + ", " +
                  reinterpret_cast<const char*>(glGetString(GL_VERSION));
  GLint max_samples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  if (samples_ > max_samples) samples_ = max_samples;

  const auto make_fbo = [&](GLuint& fbo, GLuint& color, GLuint* depth, int s) {
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glGenRenderbuffers(1, &color);
    glBindRenderbuffer(GL_RENDERBUFFER, color);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, s > 1 ? s : 0, GL_RGBA8, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    if (depth) {
      glGenRenderbuffers(1, depth);
      glBindRenderbuffer(GL_RENDERBUFFER, *depth);
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, s > 1 ? s : 0, GL_DEPTH_COMPONENT24, width, height);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, *depth);
    }
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw Error("render: the offscreen framebuffer is incomplete");
  };
  make_fbo(e.draw_fbo, e.draw_color, &e.draw_depth, samples_);
  if (samples_ > 1) make_fbo(e.resolve_fbo, e.resolve_color, nullptr, 1);
  bind();
}

OffscreenContext::~OffscreenContext() {
  Egl& e = *egl_;
  if (e.context != EGL_NO_CONTEXT) {
    const GLuint fbos[] = {e.draw_fbo, e.resolve_fbo};
    const GLuint rbs[] = {e.draw_color, e.draw_depth, e.resolve_color};
    glDeleteFramebuffers(2, fbos);
    glDeleteRenderbuffers(3, rbs);
    eglMakeCurrent(e.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(e.display, e.context);
  }
  if (e.display != EGL_NO_DISPLAY) eglTerminate(e.display);
}

void OffscreenContext::bind() { glBindFramebuffer(GL_FRAMEBUFFER, egl_->draw_fbo); }

const char* OffscreenContext::description() const { return egl_->description.c_str(); }

void OffscreenContext::read(Image& out) {
  Egl& e = *egl_;
  GLuint source = e.draw_fbo;
  if (samples_ > 1) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, e.draw_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, e.resolve_fbo);
    glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    source = e.resolve_fbo;
  }
  glBindFramebuffer(GL_READ_FRAMEBUFFER, source);
  out.width = width_;
  out.height = height_;
  std::vector<std::uint8_t>& rgba = e.rgba;  // kept: no per-frame mmap/munmap of 4 MB (see keep_rendering_off_cpu)
  rgba.resize(std::size_t(width_) * std::size_t(height_) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  out.rgb.resize(std::size_t(width_) * std::size_t(height_) * 3);
  for (int y = 0; y < height_; ++y)  // GL's rows go bottom to top
    for (int x = 0; x < width_; ++x)
      for (int k = 0; k < 3; ++k)
        out.rgb[3 * (std::size_t(y) * width_ + x) + k] = rgba[4 * (std::size_t(height_ - 1 - y) * width_ + x) + k];
  bind();
}

void keep_rendering_off_cpu(int cpu) {
  const unsigned n = std::thread::hardware_concurrency();
  if (n < 2 || cpu < 0 || unsigned(cpu) >= n) return;
  cpu_set_t set;
  CPU_ZERO(&set);
  for (unsigned c = 0; c < n; ++c)
    if (int(c) != cpu) CPU_SET(c, &set);
  pthread_setaffinity_np(pthread_self(), sizeof set, &set);
  setenv("LP_NUM_THREADS", std::to_string(n - 1).c_str(), 0);
  // Every munmap in this process sends a TLB-shootdown interrupt to each CPU running one of its
  // threads — the haptic thread's too. Frames allocate and free large buffers (glibc maps blocks
  // over 128 KB and returns freed heap tops), so keep freed memory in the process instead.
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
}

void write_png(const char* path, const Image& image) {
  FILE* f = std::fopen(path, "wb");
  if (!f) throw Error(std::string(path) + ": cannot write the PNG");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    throw Error(std::string(path) + ": PNG encoding failed");
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 3);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y)
    png_write_row(png, const_cast<png_bytep>(image.at(0, y)));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fclose(f) != 0) throw Error(std::string(path) + ": cannot write the PNG");
}

}  // namespace trocar

namespace trocar {

Image read_png(const char* path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path))
    throw Error(std::string(path) + ": cannot read the PNG: " + png.message);
  png.format = PNG_FORMAT_RGB;
  Image img;
  img.width = int(png.width);
  img.height = int(png.height);
  img.rgb.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, img.rgb.data(), 0, nullptr)) {
    const std::string why = png.message;
    png_image_free(&png);
    throw Error(std::string(path) + ": cannot decode the PNG: " + why);
  }
  return img;
}

}  // namespace trocar
