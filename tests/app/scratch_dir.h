// A fresh temporary folder per test, removed afterwards, and helpers to write scene files into it. The folder
// name holds the process id, so two checkouts running the same test at once do not share (and delete) it.
#pragma once
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

namespace wobble::testing {

inline std::filesystem::path sourceDir() { return WOBBLE_SOURCE_DIR; }

class ScratchDir : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("wobble_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" + std::to_string(getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  const std::filesystem::path& dir() const { return dir_; }
  // The shipped cat texture at textures/cat.png beside the test's scene files.
  void copyCatTexture() const {
    std::filesystem::create_directories(dir_ / "textures");
    std::filesystem::copy_file(sourceDir() / "scenes/textures/cat.png", dir_ / "textures/cat.png",
                               std::filesystem::copy_options::overwrite_existing);
  }

 private:
  std::filesystem::path dir_;
};

}  // namespace wobble::testing
