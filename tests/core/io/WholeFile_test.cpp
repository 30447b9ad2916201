// SPDX-License-Identifier: Apache-2.0
// Output files are written whole or not at all: a full disk (simulated by a file-size limit)
// leaves neither half a file nor the partial one, and the file that was there stays.

#include "io/WholeFile.h"

#include <sys/resource.h>

#include <csignal>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

std::string contentsOf(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

struct Folder {
  std::filesystem::path path = std::filesystem::temp_directory_path() /
                               ("tissuesim-wholefile-" + std::to_string(::getpid()));
  Folder() { std::filesystem::create_directories(path); }
  ~Folder() { std::filesystem::remove_all(path); }
};

TEST(WholeFile, WritesTheBytesAndLeavesNoPartialFile) {
  const Folder folder;
  const std::filesystem::path file = folder.path / "out.csv";
  writeWholeFile(file, "a,b\n1,2\n");
  EXPECT_EQ(contentsOf(file), "a,b\n1,2\n");
  writeWholeFile(file, "c\n");  // replaced whole
  EXPECT_EQ(contentsOf(file), "c\n");
  EXPECT_FALSE(std::filesystem::exists(folder.path / "out.csv.partial"));
}

TEST(WholeFile, AFullDiskLeavesTheOldFileAndNothingElse) {
  const Folder folder;
  const std::filesystem::path file = folder.path / "export.msh";
  writeWholeFile(file, "the old export\n");
  // A file-size limit of 4 kB stands for the disk filling up: writes past it fail (EFBIG, and
  // SIGXFSZ, ignored here, as a full disk raises no signal).
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  const auto previousHandler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = saved;
  small.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  std::string message;
  try {
    writeWholeFile(file, std::string(1 << 20, 'x'));
  } catch (const std::runtime_error& error) {
    message = error.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, previousHandler);
  EXPECT_NE(message.find("cannot write " + file.string() + " ("), std::string::npos) << message;
  EXPECT_EQ(contentsOf(file), "the old export\n");
  EXPECT_FALSE(std::filesystem::exists(folder.path / "export.msh.partial"));
}

TEST(WholeFile, AMissingFolderIsNamed) {
  std::string message;
  try {
    writeWholeFile("/no-such-folder/out.csv", "x");
  } catch (const std::runtime_error& error) {
    message = error.what();
  }
  EXPECT_EQ(message, "cannot write /no-such-folder/out.csv (No such file or directory)");
}

}  // namespace
}  // namespace tissuesim
