#pragma once
/// Writing and reading session recordings (recording_format.h, docs/recording.md).
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "trocar/runtime/recording_format.h"
#include "trocar/runtime/spsc_ring.h"

namespace trocar {

/// What the recording's header says.
struct RecordingHeader {
  std::uint32_t instruments = 0;  ///< instruments in the records
  double haptic_rate_hz = 0;      ///< haptic rate of the session (Hz)
  double timestep = 0;            ///< scene timestep (s)
  std::uint32_t mode = 0;         ///< 0 multirate, 1 lock-step
  /// The kernel path the session ran on (core/cpu_features.h: "avx512", "avx2", "portable", …);
  /// state hashes are comparable only between recordings of one path. kUnknownKernelPath when
  /// read from a version 1 file.
  std::string kernel_path = kUnknownKernelPath;
  std::uint32_t version = kRecordingVersion;  ///< the file's format version (as read; always written current)
  std::string scene_path;         ///< absolute path of the scene file (resolves its meshes)
  std::string scene_text;         ///< the scene file's text as it was run
};

/// Records from the haptic and physics threads (one producer each, SPSC rings) written by a
/// background thread in blocks of at most kBlockRecords, flushed at least every kFlushPeriod.
/// Opening throws trocar::Error naming the file; a write error later is kept and reported by
/// finish() (the real-time threads never see it).
class RecordingWriter {
 public:
  static constexpr std::size_t kBlockRecords = 256;        ///< records per block at most
  static constexpr double kFlushPeriod = 0.05;             ///< s between flushes at most

  /// Creates `file` and writes the header. ring_capacity: records each ring holds.
  RecordingWriter(const std::filesystem::path& file, const RecordingHeader& header,
                  std::size_t ring_capacity = 1 << 15);
  ~RecordingWriter();
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;

  /// From the haptic thread: never blocks; false (and counted) when the ring is full.
  bool push_tick(const TickRecord& r) { return ticks_.push(r); }
  /// From the physics thread: never blocks; false (and counted) when the ring is full.
  bool push_step(const StepRecord& r) { return steps_.push(r); }
  /// Drains, writes the end record, closes. Throws trocar::Error if any write failed.
  void finish(EndRecord end);
  /// Records lost to full rings so far.
  std::uint64_t dropped() const { return ticks_.dropped() + steps_.dropped(); }
  std::uint64_t ticks_written() const { return ticks_written_; }  ///< after finish()
  std::uint64_t steps_written() const { return steps_written_; }  ///< after finish()

 private:
  void run();
  void drain();
  void write_block(const std::vector<unsigned char>& payload, std::uint32_t records);
  void append_record(const void* record, std::size_t bytes);
  void flush_block();

  std::filesystem::path file_;
  int fd_ = -1;
  SpscRing<TickRecord> ticks_;
  SpscRing<StepRecord> steps_;
  std::vector<unsigned char> block_;
  std::uint32_t block_records_ = 0;
  std::uint64_t ticks_written_ = 0;
  std::uint64_t steps_written_ = 0;
  std::string error_;                ///< first write error (written by the writer thread only)
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

/// A recording read back.
struct Recording {
  RecordingHeader header;
  std::vector<TickRecord> ticks;       ///< in order
  std::vector<StepRecord> steps;       ///< in order
  std::optional<EndRecord> end;        ///< absent when the file ends early
  std::uint64_t complete_bytes = 0;    ///< bytes up to the end of the last complete block
  std::uint64_t file_bytes = 0;        ///< size of the file
};

/// Reads a recording. strict: a truncated or corrupt block, or a missing end record, throws
/// trocar::FileError naming the file and the byte offset. Not strict: reading stops at the first
/// bad block and `end` tells whether the file was complete (for plotting a killed session); the
/// recording then holds the records of the complete blocks only.
/// A bad header always throws. Besides the checksums, a block is bad when a record's replay
/// inputs are out of range: more instruments than the header's, an unknown step mode or device
/// status, a non-finite pose, jaw or dt, a dt ≤ 0, a commanded rotation that is not a unit
/// quaternion.
Recording read_recording(const std::filesystem::path& file, bool strict);

/// The same from the file's bytes; `file` names it in errors.
Recording parse_recording(std::string_view bytes, const std::string& file, bool strict);

/// The checksum a block of a file of format `version` carries over its payload (FNV-1a, 64-bit).
std::uint64_t block_checksum(const unsigned char* payload, std::size_t bytes, std::uint32_t version);

}  // namespace trocar
