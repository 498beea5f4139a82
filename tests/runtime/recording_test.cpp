// Session recordings: written from the two rings and read back record for record; a truncated
// or corrupted file is an error naming the file and the exact byte offset (and still readable up
// to its last complete block for plotting); a real-time run replays to the same state hash on
// its own kernel path, and says the hashes are not comparable on another.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "trocar/core/cpu_features.h"
#include "support/manual_clock.h"
#include "trocar/core/error.h"
#include "trocar/device/scripted_device.h"
#include "trocar/runtime/recording.h"
#include "trocar/runtime/runtime.h"
#include "trocar/runtime/session.h"

namespace trocar {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("trocar_" + std::to_string(::getpid()) + "_" + name);
}

RecordingHeader header() {
  RecordingHeader h;
  h.instruments = 1;
  h.haptic_rate_hz = 1000;
  h.timestep = 1e-3;
  h.scene_path = "/nowhere/scene.json";
  h.scene_text = "{\"schema\": 1}";
  return h;
}

// 600 ticks and 300 steps: several blocks of 256 records.
fs::path write_sample(const std::string& name) {
  const fs::path f = temp_file(name);
  RecordingWriter w(f, header());
  for (std::uint64_t i = 0; i < 600; ++i) {
    TickRecord t;
    t.tick = i;
    t.time_ns = static_cast<std::int64_t>(i) * 1000000;
    t.instruments = 1;
    t.instrument[0].force = {0, 0, double(i) * 1e-3};
    EXPECT_TRUE(w.push_tick(t));
    if (i % 2 == 0) {
      StepRecord s;
      s.step = i / 2 + 1;
      s.dt = 1e-3;
      s.instruments = 1;
      EXPECT_TRUE(w.push_step(s));
    }
  }
  EndRecord end;
  end.state_hash = 0x1234abcdULL;
  w.finish(end);
  EXPECT_EQ(w.ticks_written(), 600u);
  EXPECT_EQ(w.steps_written(), 300u);
  return f;
}

TEST(Recording, ReadsBackEveryRecordInOrder) {
  const fs::path f = write_sample("roundtrip.trec");
  const Recording r = read_recording(f, true);
  EXPECT_EQ(r.header.scene_path, "/nowhere/scene.json");
  EXPECT_EQ(r.header.scene_text, "{\"schema\": 1}");
  EXPECT_DOUBLE_EQ(r.header.haptic_rate_hz, 1000);
  ASSERT_EQ(r.ticks.size(), 600u);
  ASSERT_EQ(r.steps.size(), 300u);
  for (std::size_t i = 0; i < r.ticks.size(); ++i) {
    EXPECT_EQ(r.ticks[i].tick, i);
    EXPECT_DOUBLE_EQ(r.ticks[i].instrument[0].force[2], double(i) * 1e-3);
  }
  for (std::size_t i = 0; i < r.steps.size(); ++i) EXPECT_EQ(r.steps[i].step, i + 1);
  ASSERT_TRUE(r.end.has_value());
  EXPECT_EQ(r.end->state_hash, 0x1234abcdULL);
  EXPECT_EQ(r.end->ticks, 600u);
  EXPECT_EQ(r.complete_bytes, r.file_bytes);
  fs::remove(f);
}

// A recording built byte by byte here (not by RecordingWriter, whose blocks follow its thread's
// timing), so that every offset below is known: the header, then
//   block A: ticks 0 and 1;  block B: step 1 and tick 2;  block C: the end record.
constexpr std::size_t kBlockHeaderBytes = 24;  // "TRBK", records, payload bytes, reserved, checksum

// FNV-1a, 64-bit (offset basis, prime); version 1 files used a basis short of its last digit.
std::uint64_t fnv1a_64(const std::string& bytes, std::uint64_t basis = 14695981039346656037ULL) {
  std::uint64_t h = basis;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ULL;
  return h;
}

template <typename T>
void append(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

void append_string(std::string& out, const std::string& s) {
  append(out, static_cast<std::uint64_t>(s.size()));
  out += s;
}

// The header as version `version` writes it (version 1 has no kernel path).
std::string header_bytes(std::uint32_t version, const RecordingHeader& h) {
  std::string out(kRecordingMagic, sizeof kRecordingMagic);
  append(out, version);
  append(out, h.instruments);
  append(out, h.haptic_rate_hz);
  append(out, h.timestep);
  append(out, h.mode);
  if (version >= 2) append_string(out, h.kernel_path);
  append_string(out, h.scene_path);
  append_string(out, h.scene_text);
  return out;
}

std::string block_bytes(const std::string& payload, std::uint32_t records, std::uint32_t version = kRecordingVersion) {
  std::string out(kBlockMagic, sizeof kBlockMagic);
  append(out, records);
  append(out, static_cast<std::uint32_t>(payload.size()));
  append(out, std::uint32_t{0});
  append(out, fnv1a_64(payload, version == 1 ? 1469598103934665603ULL : 14695981039346656037ULL));
  return out + payload;
}

TickRecord tick(std::uint64_t i) {
  TickRecord t;
  t.tick = i;
  t.instruments = 1;
  t.instrument[0].device_pose = {1, 0, 0, 0, 0, 0, 0.01 * double(i)};
  return t;
}

struct HandBuilt {
  std::string bytes;
  std::size_t header = 0;   // bytes of the header
  std::size_t block_b = 0;  // offset of block B
  std::size_t block_c = 0;  // offset of block C
};

HandBuilt hand_built(std::uint32_t version = kRecordingVersion, const RecordingHeader& h = header()) {
  HandBuilt f;
  f.bytes = header_bytes(version, h);
  f.header = f.bytes.size();
  std::string a, b, c;
  append(a, tick(0));
  append(a, tick(1));
  StepRecord s;
  s.step = 1;
  s.dt = 1e-3;
  s.instruments = 1;
  s.instrument[0].mode = 2;
  s.instrument[0].pose = {1, 0, 0, 0, 0, 0, 0.02};
  append(b, s);
  append(b, tick(2));
  EndRecord e;
  e.steps = 1;
  e.ticks = 3;
  e.state_hash = 0xfeedULL;
  append(c, e);
  f.bytes += block_bytes(a, 2, version);
  f.block_b = f.bytes.size();
  f.bytes += block_bytes(b, 2, version);
  f.block_c = f.bytes.size();
  f.bytes += block_bytes(c, 1, version);
  return f;
}

TEST(Recording, HandBuiltLayoutIsWhatTheOffsetsBelowAssume) {
  const HandBuilt f = hand_built();
  // magic 8, version 4, instruments 4, rate 8, timestep 8, mode 4, then three u64-sized strings
  EXPECT_EQ(f.header, 36 + (8 + 7) + (8 + 19) + (8 + 13));  // "unknown", "/nowhere/scene.json", "{\"schema\": 1}"
  EXPECT_EQ(f.block_b, f.header + kBlockHeaderBytes + 2 * sizeof(TickRecord));
  EXPECT_EQ(f.block_c, f.block_b + kBlockHeaderBytes + sizeof(StepRecord) + sizeof(TickRecord));
  EXPECT_EQ(f.bytes.size(), f.block_c + kBlockHeaderBytes + sizeof(EndRecord));
  const Recording r = parse_recording(f.bytes, "hand.trec", true);
  ASSERT_EQ(r.ticks.size(), 3u);
  ASSERT_EQ(r.steps.size(), 1u);
  EXPECT_EQ(r.ticks[2].tick, 2u);
  EXPECT_EQ(r.end->state_hash, 0xfeedULL);
  EXPECT_EQ(r.complete_bytes, f.bytes.size());
}

TEST(Recording, CutInsideTheLastPayloadNamesItsFirstByteAndKeepsTheBlocksBefore) {
  const HandBuilt f = hand_built();
  const std::size_t cut = f.block_c + kBlockHeaderBytes + 10;  // 10 of the end record's 40 bytes
  const std::string cut_bytes = f.bytes.substr(0, cut);
  try {
    parse_recording(cut_bytes, "cut.trec", true);
    FAIL() << "a truncated recording must not read";
  } catch (const FileError& e) {
    EXPECT_EQ(e.file(), "cut.trec");
    EXPECT_EQ(e.where().kind, FileLocation::Kind::kByte);
    EXPECT_EQ(e.where().value, f.block_c + kBlockHeaderBytes);  // where the payload starts
    EXPECT_EQ(e.reason(), "truncated: a block's payload needs 40 bytes, 10 left");
  }
  const Recording partial = parse_recording(cut_bytes, "cut.trec", false);  // for plotting a killed session
  EXPECT_FALSE(partial.end.has_value());
  EXPECT_EQ(partial.ticks.size(), 3u);  // blocks A and B
  EXPECT_EQ(partial.steps.size(), 1u);
  EXPECT_EQ(partial.complete_bytes, f.block_c);
  EXPECT_EQ(partial.file_bytes, cut);
}

TEST(Recording, CutInsideABlockHeaderNamesTheBlock) {
  const HandBuilt f = hand_built();
  const std::string cut_bytes = f.bytes.substr(0, f.block_b + 10);
  try {
    parse_recording(cut_bytes, "cut.trec", true);
    FAIL() << "a truncated recording must not read";
  } catch (const FileError& e) {
    EXPECT_EQ(e.where().value, f.block_b);
    EXPECT_EQ(e.reason(), "truncated: a block header needs 24 bytes, 10 left");
  }
  const Recording partial = parse_recording(cut_bytes, "cut.trec", false);
  EXPECT_EQ(partial.ticks.size(), 2u);  // block A only
  EXPECT_EQ(partial.steps.size(), 0u);
  EXPECT_EQ(partial.complete_bytes, f.block_b);
}

TEST(Recording, CutAtABlockBoundaryIsAMissingEndRecordThere) {
  const HandBuilt f = hand_built();
  try {
    parse_recording(f.bytes.substr(0, f.block_c), "cut.trec", true);
    FAIL();
  } catch (const FileError& e) {
    EXPECT_EQ(e.where().value, f.block_c);
    EXPECT_EQ(e.reason(), "truncated: no end record (the session did not finish)");
  }
}

TEST(Recording, CorruptByteIsAChecksumErrorAtItsBlock) {
  HandBuilt f = hand_built();
  const std::size_t damaged = f.block_b + kBlockHeaderBytes + 100;  // inside step 1
  f.bytes[damaged] = static_cast<char>(f.bytes[damaged] ^ 0x5a);
  try {
    parse_recording(f.bytes, "corrupt.trec", true);
    FAIL() << "a corrupt recording must not read";
  } catch (const FileError& e) {
    EXPECT_EQ(e.where().kind, FileLocation::Kind::kByte);
    EXPECT_EQ(e.where().value, f.block_b);  // the start of the damaged block
    EXPECT_EQ(e.reason(), "block checksum mismatch (corrupt data)");
  }
  const Recording partial = parse_recording(f.bytes, "corrupt.trec", false);
  EXPECT_EQ(partial.ticks.size(), 2u);
  EXPECT_EQ(partial.steps.size(), 0u);
  EXPECT_EQ(partial.complete_bytes, f.block_b);
}

TEST(Recording, WrittenFileCutMidBlockKeepsExactlyItsCompleteBlocks) {
  // The writer's own file: its block boundaries (walked here from the block headers) are where
  // the lenient reader must stop, to the byte.
  const fs::path f = write_sample("truncated.trec");
  std::ifstream in(f, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t header_size = header_bytes(kRecordingVersion, header()).size();
  std::vector<std::size_t> block_at;
  std::vector<std::uint32_t> block_records;
  for (std::size_t at = header_size; at < bytes.size();) {
    block_at.push_back(at);
    std::uint32_t records = 0, payload = 0;
    std::memcpy(&records, bytes.data() + at + 4, 4);
    std::memcpy(&payload, bytes.data() + at + 8, 4);
    block_records.push_back(records);
    at += kBlockHeaderBytes + payload;
  }
  ASSERT_GE(block_at.size(), 4u);  // 901 records, at most 256 a block
  const std::size_t last = block_at.back();
  const std::size_t cut = bytes.size() - 10;  // inside the last block's payload
  try {
    parse_recording(bytes.substr(0, cut), f.string(), true);
    FAIL() << "a truncated recording must not read";
  } catch (const FileError& e) {
    EXPECT_EQ(e.where().value, last + kBlockHeaderBytes);
  }
  const Recording partial = parse_recording(bytes.substr(0, cut), f.string(), false);
  std::size_t kept_records = 0;
  for (std::size_t i = 0; i + 1 < block_records.size(); ++i) kept_records += block_records[i];
  EXPECT_EQ(partial.complete_bytes, last);
  EXPECT_EQ(partial.ticks.size() + partial.steps.size(), kept_records);
  EXPECT_FALSE(partial.end.has_value());
  fs::remove(f);
}

TEST(Recording, HeaderStatesItsKernelPath) {
  RecordingHeader h = header();
  h.kernel_path = "avx2";
  const fs::path f = temp_file("kernel.trec");
  {
    RecordingWriter w(f, h);
    w.finish(EndRecord{});
  }
  const Recording r = read_recording(f, true);
  EXPECT_EQ(r.header.version, kRecordingVersion);
  EXPECT_EQ(r.header.kernel_path, "avx2");
  EXPECT_EQ(r.header.scene_path, "/nowhere/scene.json");
  // On disk right after the mode (byte 36): u64 length 4, then the name.
  std::ifstream in(f, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::uint64_t n = 0;
  std::memcpy(&n, bytes.data() + 36, 8);
  EXPECT_EQ(n, 4u);
  EXPECT_EQ(bytes.substr(44, 4), "avx2");
  fs::remove(f);
}

TEST(Recording, Version1HeaderReadsWithAnUnknownKernelPath) {
  const HandBuilt f = hand_built(1);
  EXPECT_EQ(f.header, 36 + (8 + 19) + (8 + 13));  // no kernel path
  const Recording r = parse_recording(f.bytes, "old.trec", true);
  EXPECT_EQ(r.header.version, 1u);
  EXPECT_EQ(r.header.kernel_path, "unknown");
  EXPECT_EQ(r.header.scene_path, "/nowhere/scene.json");
  EXPECT_EQ(r.header.scene_text, "{\"schema\": 1}");
  EXPECT_EQ(r.ticks.size(), 3u);
  EXPECT_EQ(r.end->state_hash, 0xfeedULL);
}

// A recording's header and records are checked before a replay feeds them to a simulation.
std::string header_error(const RecordingHeader& h, std::uint32_t version = kRecordingVersion) {
  try {
    parse_recording(hand_built(version, h).bytes, "bad.trec", true);
  } catch (const FileError& e) {
    return std::to_string(e.where().value) + ": " + e.reason();
  }
  return "read";
}

TEST(Recording, BadHeaderFieldsAreErrorsAtTheirByte) {
  RecordingHeader h = header();
  h.haptic_rate_hz = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(header_error(h), "16: haptic rate must be finite and > 0");
  h = header();
  h.timestep = 0;
  EXPECT_EQ(header_error(h), "24: timestep must be finite and > 0");
  h = header();
  h.mode = 7;
  EXPECT_EQ(header_error(h), "32: mode 7 (0 multirate, 1 lock-step)");
  h = header();
  h.kernel_path = "a\nb";
  EXPECT_EQ(header_error(h), "36: the kernel path is not a name");
  h = header();
  h.instruments = 1;
  EXPECT_EQ(header_error(h, 3), "8: version 3 (this build reads 1 to 2)");
  EXPECT_EQ(header_error(h, 0), "8: version 0 (this build reads 1 to 2)");
}

// Block B's step replaced by `s`: the error names the step's first byte.
std::string step_error(const StepRecord& s) {
  HandBuilt f = hand_built();
  std::string b;
  append(b, s);
  append(b, tick(2));
  f.bytes.replace(f.block_b, kBlockHeaderBytes + b.size(), block_bytes(b, 2));
  try {
    parse_recording(f.bytes, "bad.trec", true);
  } catch (const FileError& e) {
    EXPECT_EQ(e.where().value, f.block_b + kBlockHeaderBytes);
    return e.reason();
  }
  return "read";
}

TEST(Recording, StepRecordsAReplayCannotTakeAreErrors) {
  StepRecord s;
  s.step = 1;
  s.dt = 1e-3;
  s.instruments = 1;
  s.instrument[0].mode = 1;
  s.instrument[0].pose = {1, 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(step_error(s), "read");
  StepRecord bad = s;
  bad.instruments = 2;  // the header has 1: the simulation has no instrument 1
  EXPECT_EQ(step_error(bad), "step 1 has 2 instruments, the header 1");
  bad = s;
  bad.instruments = 1000;  // beyond the record's own array
  EXPECT_EQ(step_error(bad), "step 1 has 1000 instruments, the header 1");
  bad = s;
  bad.dt = std::numeric_limits<double>::infinity();
  EXPECT_EQ(step_error(bad), "step 1: dt must be finite and > 0");
  bad = s;
  bad.dt = -1e-3;
  EXPECT_EQ(step_error(bad), "step 1: dt must be finite and > 0");
  bad = s;
  bad.instrument[0].mode = 3;
  EXPECT_EQ(step_error(bad), "step 1: unknown instrument mode 3");
  bad = s;
  bad.instrument[0].pose[5] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(step_error(bad), "step 1: non-finite pose or jaw");
  bad = s;
  bad.instrument[0].jaw = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(step_error(bad), "step 1: non-finite pose or jaw");
  bad = s;
  bad.instrument[0].pose = {2, 0, 0, 0, 0, 0, 0};  // would scale the instrument by 4
  EXPECT_EQ(step_error(bad), "step 1: the rotation is not a unit quaternion");
  bad = s;
  bad.instrument[0].mode = 0;  // keyframes: the pose is not read, so zeros are fine
  bad.instrument[0].pose = {};
  EXPECT_EQ(step_error(bad), "read");
}

TEST(Recording, BadRecordDropsItsWholeBlockWhenReadLeniently) {
  HandBuilt f = hand_built();
  std::string b;
  append(b, tick(2));  // good, then a bad step: neither may be kept
  StepRecord s;
  s.step = 1;
  s.dt = std::numeric_limits<double>::quiet_NaN();
  append(b, s);
  f.bytes.replace(f.block_b, kBlockHeaderBytes + b.size(), block_bytes(b, 2));
  const Recording r = parse_recording(f.bytes, "bad.trec", false);
  EXPECT_EQ(r.ticks.size(), 2u);
  EXPECT_EQ(r.steps.size(), 0u);
  EXPECT_EQ(r.complete_bytes, f.block_b);
}

TEST(Recording, NotARecordingIsAnErrorAtByteZero) {
  const fs::path f = temp_file("garbage.trec");
  std::ofstream(f) << "hello, this is not a recording";
  try {
    read_recording(f, true);
    FAIL();
  } catch (const FileError& e) {
    EXPECT_EQ(e.where().value, 0u);
  }
  EXPECT_THROW(read_recording(temp_file("missing.trec"), true), FileError);
  fs::remove(f);
}

// A real-time session of the shipped press scene, then its replay in lock-step.
void record_and_replay(bool lockstep) {
  const fs::path scene_file = fs::path(TROCAR_TEST_SCENES) / "probe_press_slide.json";
  Scene scene = load_scene(scene_file);
  scene.settings.measure_penetration = false;
  const std::vector<DeviceSpec> devices = scene.devices;
  Simulation sim(std::move(scene.world), scene.settings);
  const fs::path f = temp_file(lockstep ? "lockstep.trec" : "multirate.trec");
  RuntimeSettings settings;
  settings.lockstep = lockstep;
  settings.duration = 0;  // until stopped, after 800 periods of the manual clock
  settings.realtime_scheduling = false;
  test::ManualClock clock;
  settings.clock = &clock;
  RecordingWriter writer(f, session_header(scene_file, read_scene_text(scene_file), sim, settings));
  // The probe starts just above the lobe (its top is near z = 33 mm) and presses 13 mm in 0.3 s.
  std::vector<RuntimeChannel> channels = make_channels(devices, sim.world());
  Keyframe start, pressed;
  start.position = Vec3(0, 0, 0.034);
  pressed.t = 0.3;
  pressed.position = Vec3(0, 0, 0.021);
  channels[0].device = std::make_unique<ScriptedDevice>(KeyframeMotion({start, pressed}));
  Runtime runtime(sim, std::move(channels), settings, &writer);
  const RuntimeReport report = test::run_for_periods(runtime, clock, lockstep ? 1 : 2, 800, 1000000);
  finish_recording(writer, sim);
  EXPECT_EQ(report.ticks, 801u);  // 800 periods and the stopping one
  EXPECT_GE(report.physics_steps, 800u);  // lock-step: one a tick; multirate: one a period (+ the stop's)
  EXPECT_EQ(report.recording_dropped, 0u);
  const ReplayResult r = replay_recording(f);
  EXPECT_EQ(r.steps, report.physics_steps);
  EXPECT_EQ(r.recorded_hash, sim.state_hash());
  EXPECT_TRUE(r.matches()) << hash_hex(r.state_hash) << " vs " << hash_hex(r.recorded_hash);
  // The session really touched the organ (a replay of free motion would prove little).
  const Recording rec = read_recording(f, true);
  double peak = 0;
  for (const StepRecord& s : rec.steps) peak = std::max(peak, std::abs(s.instrument[0].force[2]));
  EXPECT_GT(peak, 0.05);
  fs::remove(f);
}

TEST(Replay, LockstepSessionReplaysBitForBit) { record_and_replay(true); }
TEST(Replay, MultirateSessionReplaysBitForBit) { record_and_replay(false); }

TEST(Replay, VerdictComparesHashesOnlyOnOneKernelPath) {
  ReplayResult r;
  r.state_hash = 1;
  r.recorded_hash = 2;
  r.recorded_kernel_path = "avx2";
  r.kernel_path = "portable";
  EXPECT_FALSE(r.comparable());
  EXPECT_EQ(r.verdict(), "recorded on avx2, replaying on portable: hashes are not comparable across kernel paths");
  r.recorded_hash = 1;  // even an equal hash proves nothing across paths
  EXPECT_FALSE(r.comparable());
  r.kernel_path = "avx2";
  EXPECT_EQ(r.verdict(), "identical");
  r.recorded_hash = 2;
  EXPECT_EQ(r.verdict(), "DIFFERENT");
  r.recorded_kernel_path = "unknown";  // a version 1 recording: compared, with a note on a mismatch
  EXPECT_TRUE(r.comparable());
  EXPECT_EQ(r.verdict(), "DIFFERENT (the recording does not state its kernel path; replaying on avx2, and a "
                         "recording made on another path differs)");
  r.recorded_hash = 1;
  EXPECT_EQ(r.verdict(), "identical");
}

// Caps the kernel path for one test and restores it after.
struct KernelPathCap {
  explicit KernelPathCap(KernelPath widest) { cap_kernel_path(widest); }
  ~KernelPathCap() { cap_kernel_path(KernelPath::kAvx512); }
};

TEST(Replay, SessionRecordedOnTheVectorPathReplayedOnThePortableOneSaysSo) {
  const fs::path scene_file = fs::path(TROCAR_TEST_SCENES) / "probe_press_slide.json";
  const std::string native = kernel_path_name(kernel_path());
  Scene scene = load_scene(scene_file);
  scene.settings.measure_penetration = false;
  Simulation sim(std::move(scene.world), scene.settings);
  const fs::path f = temp_file("paths.trec");
  RuntimeSettings settings;
  settings.lockstep = true;
  settings.duration = 0.1;
  settings.realtime_scheduling = false;
  RecordingWriter writer(f, session_header(scene_file, read_scene_text(scene_file), sim, settings));
  Runtime runtime(sim, make_channels(scene.devices, sim.world()), settings, &writer);
  runtime.run();
  finish_recording(writer, sim);
  EXPECT_EQ(read_recording(f, true).header.kernel_path, native);
  {
    const KernelPathCap portable(KernelPath::kPortable);
    EXPECT_FALSE(cpu_has_avx2());
    const ReplayResult r = replay_recording(f);
    EXPECT_EQ(r.recorded_kernel_path, native);
    EXPECT_EQ(r.kernel_path, "portable");
    if (native != "portable") {  // the machines CI runs on
      EXPECT_FALSE(r.comparable());
      EXPECT_EQ(r.verdict(), "recorded on " + native + ", replaying on portable: hashes are not comparable across kernel paths");
    } else {  // a CPU without AVX2: one path, so the exact check
      EXPECT_TRUE(r.comparable());
      EXPECT_EQ(r.verdict(), "identical");
    }
  }
  const ReplayResult same = replay_recording(f);  // back on the recording's own path: exact
  EXPECT_EQ(same.kernel_path, native);
  EXPECT_EQ(same.verdict(), "identical");
  fs::remove(f);
}

}  // namespace
}  // namespace trocar
