// Session recordings: written from the two rings and read back record for record; a truncated
// or corrupted file is an error naming the file and the byte offset (and still readable up to
// its last complete block for plotting); a real-time run replays to the same state hash.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

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

TEST(Recording, TruncatedFileNamesTheByteOffsetAndKeepsCompleteBlocks) {
  const fs::path f = write_sample("truncated.trec");
  const Recording whole = read_recording(f, true);
  const std::uint64_t cut = whole.file_bytes - 100;  // inside the last block
  fs::resize_file(f, cut);
  try {
    read_recording(f, true);
    FAIL() << "a truncated recording must not read";
  } catch (const FileError& e) {
    EXPECT_EQ(e.file(), f.string());
    EXPECT_EQ(e.where().kind, FileLocation::Kind::kByte);
    EXPECT_LE(e.where().value, cut);
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  const Recording partial = read_recording(f, false);  // for plotting a killed session
  EXPECT_FALSE(partial.end.has_value());
  EXPECT_GT(partial.ticks.size(), 300u);
  EXPECT_LT(partial.complete_bytes, cut);
  fs::remove(f);
}

TEST(Recording, CorruptByteIsAChecksumErrorAtItsBlock) {
  const fs::path f = write_sample("corrupt.trec");
  const Recording whole = read_recording(f, true);
  {
    std::fstream io(f, std::ios::in | std::ios::out | std::ios::binary);
    io.seekp(static_cast<std::streamoff>(whole.file_bytes / 2));
    char c = 0;
    io.read(&c, 1);
    c = static_cast<char>(c ^ 0x5a);
    io.seekp(static_cast<std::streamoff>(whole.file_bytes / 2));
    io.write(&c, 1);
  }
  try {
    read_recording(f, true);
    FAIL() << "a corrupt recording must not read";
  } catch (const FileError& e) {
    EXPECT_EQ(e.where().kind, FileLocation::Kind::kByte);
    EXPECT_LT(e.where().value, whole.file_bytes / 2);  // the start of the damaged block
    EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
  }
  fs::remove(f);
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

}  // namespace
}  // namespace trocar
