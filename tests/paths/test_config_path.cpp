// plc/config_path.hpp: the one place that says where a file named by a
// config is (docs/config.md, "Relative paths"), for every kind of config
// path: a bare file name, ./x, ../x and an absolute one.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "plc/config_path.hpp"
#include "runtime/test_helpers.hpp"

namespace {

namespace fs = std::filesystem;

TEST(ConfigPath, TheFolderOfABareConfigNameIsTheCurrentOne) {
  // Issue 21 point 1: the folder of "cell.yaml" is "", and
  // std::filesystem::absolute("") threw (plcrun ended with exit 134).
  EXPECT_EQ(plc::config_folder("cell.yaml"), ".");
  EXPECT_EQ(plc::config_folder("./cell.yaml"), ".");
  EXPECT_EQ(plc::config_folder("../dir/cell.yaml"), "../dir");
  EXPECT_EQ(plc::config_folder("dir/cell.yaml"), "dir");
  EXPECT_EQ(plc::config_folder("/abs/dir/cell.yaml"), "/abs/dir");
  EXPECT_EQ(plc::config_folder("/cell.yaml"), "/");
  EXPECT_EQ(plc::config_folder(""), ".");
}

TEST(ConfigPath, ARelativePathIsTakenFromTheConfigsFolder) {
  struct Row {
    const char* config;
    const char* path;
    const char* expected;
  };
  const Row rows[] = {
      {"cell.yaml", "cell.retain", "cell.retain"},
      {"cell.yaml", "./cell.retain", "cell.retain"},
      {"cell.yaml", "../x/cell.retain", "../x/cell.retain"},
      {"cell.yaml", "/abs/cell.retain", "/abs/cell.retain"},
      {"./cell.yaml", "build/libmycell.so", "build/libmycell.so"},
      {"./cell.yaml", "./build/libmycell.so", "build/libmycell.so"},
      {"../dir/cell.yaml", "cell.retain", "../dir/cell.retain"},
      {"../dir/cell.yaml", "./keys/hmi.key", "../dir/keys/hmi.key"},
      {"../dir/cell.yaml", "../other/hmi.key", "../dir/../other/hmi.key"},  // kernel resolves ..
      {"../dir/cell.yaml", "/abs/hmi.key", "/abs/hmi.key"},
      {"/abs/dir/cell.yaml", "file.xml", "/abs/dir/file.xml"},
      {"/abs/dir/cell.yaml", "./file.xml", "/abs/dir/file.xml"},
      {"/abs/dir/cell.yaml", "../file.xml", "/abs/dir/../file.xml"},
      {"/cell.yaml", "file.xml", "/file.xml"},
      {"cell.yaml", "", ""},  // the callers say "names no file"
  };
  for (const Row& r : rows)
    EXPECT_EQ(plc::config_relative_path(r.config, r.path), r.expected)
        << r.config << " + " << r.path;
}

TEST(ConfigPath, AbsolutePathNeverThrows) {
  std::string why;
  const auto cwd = fs::current_path().string();
  EXPECT_EQ(plc::absolute_path("x.so", why), cwd + "/x.so");
  EXPECT_EQ(plc::absolute_path("./build/../x.so", why), cwd + "/x.so");
  EXPECT_EQ(plc::absolute_path("/a/./b/../c.so", why), "/a/c.so");
  EXPECT_EQ(plc::absolute_path("", why), std::nullopt);
  EXPECT_EQ(why, "an empty path");
}

TEST(ConfigPath, ReadableFileProblemNamesWhatIsWrong) {
  const std::string dir = plctest::temp_path("cfgpath_dir");
  const std::string fifo = plctest::temp_path("cfgpath_fifo");
  const std::string file = plctest::write_temp("cfgpath_file.yaml", "cell: x\n");
  fs::create_directories(dir);
  ::unlink(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(plc::readable_file_problem(file), "");
  EXPECT_EQ(plc::readable_file_problem(""), "an empty path names no file");
  EXPECT_EQ(plc::readable_file_problem(dir), "is a folder, not a file");
  EXPECT_EQ(plc::readable_file_problem(fifo),
            "is not a regular file (a FIFO): give the file itself");
  EXPECT_EQ(plc::readable_file_problem(dir + "/none.yaml"),
            "cannot open: No such file or directory");
  fs::remove(dir);
  fs::remove(fifo);
  fs::remove(file);
}

}  // namespace
