#pragma once
// A test's input written to a fresh temporary file, removed at scope exit.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <string>

class TempFile {
 public:
  /// `suffix` keeps the file type visible to readers that look at it (".yaml", ".csv").
  TempFile(const std::string& text, const std::string& suffix) {
    static std::atomic<int> counter{0};
    path_ = testing::TempDir() + "tread_wear_test_" + std::to_string(counter++) + suffix;
    std::ofstream(path_) << text;
  }
  ~TempFile() { std::remove(path_.c_str()); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};
