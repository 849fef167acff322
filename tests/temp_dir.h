// A scratch directory for a test: fresh, named after the running test, removed (with its contents) on destruction.
#pragma once
#include <filesystem>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

namespace wobble::test {

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("wobble_render_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
             std::to_string(getpid()));  // the process id: two checkouts may run the same test at once
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  // Number of entries in the directory (to check that no temporary file was left behind).
  int entries() const {
    int n = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(path_)) ++n;
    return n;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace wobble::test
