// The tests' main: GoogleTest's, and when TROCAR_SKIP_LOG names a file, a listener that appends
// each skipped test and its reason to it, one line in one write (O_APPEND: lines from tests
// running side by side do not interleave). scripts/check-skips reads it after the run.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

namespace {

class SkipLog : public ::testing::EmptyTestEventListener {
 public:
  SkipLog(std::string path, std::string program) : path_(std::move(path)), program_(std::move(program)) {}
  void OnTestEnd(const ::testing::TestInfo& info) override {
    const ::testing::TestResult& result = *info.result();
    if (!result.Skipped()) return;
    std::string reason;
    for (int i = 0; i < result.total_part_count(); ++i)
      if (result.GetTestPartResult(i).skipped()) reason = result.GetTestPartResult(i).message();
    for (char& c : reason)
      if (c == '\n' || c == '\t') c = ' ';
    const std::string line =
        program_ + "." + info.test_suite_name() + "." + info.name() + "\t" + reason + "\n";  // ctest's name
    const int fd = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_CREAT, 0644);
    if (fd < 0) return;
    const ssize_t written = ::write(fd, line.data(), line.size());
    (void)written;  // a lost line shows as a missing skip, not a wrong one
    ::close(fd);
  }

 private:
  std::string path_, program_;
};

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (const char* log = std::getenv("TROCAR_SKIP_LOG"); log != nullptr && *log != 0)
    ::testing::UnitTest::GetInstance()->listeners().Append(
        new SkipLog(log, std::string(argv[0]).substr(std::string(argv[0]).find_last_of('/') + 1)));
  return RUN_ALL_TESTS();
}
