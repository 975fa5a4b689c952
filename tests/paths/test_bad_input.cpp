// Issue 21 point 3: no uncaught exception ends plcrun, dnslave or pndevsim
// (the shell's 134 after "terminate called after throwing ..."): bad input
// is a message naming it and exit code 2 (README, "Exit codes").
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "path_tree.hpp"

namespace pathtest {
namespace {

// A folder, a FIFO (reading it would wait for a writer for ever) and a
// file that does not exist, as the file a tool is given.
class NotAFile {
 public:
  explicit NotAFile(const std::string& test) : tree_(test) {
    dir_ = tree_.root() / "a_folder.yaml";
    fifo_ = tree_.root() / "a_fifo.yaml";
    fs::create_directories(dir_);
    ::mkfifo(fifo_.c_str(), 0600);
  }
  [[nodiscard]] std::string dir() const { return dir_.string(); }
  [[nodiscard]] std::string fifo() const { return fifo_.string(); }
  [[nodiscard]] std::string missing() const { return (tree_.root() / "none.yaml").string(); }
  [[nodiscard]] const Tree& tree() const { return tree_; }

 private:
  Tree tree_;
  fs::path dir_, fifo_;
};

struct Row {
  std::string args;
  std::string message;
};

void expect_exit_two(const std::string& program, const std::vector<Row>& rows) {
  for (const Row& r : rows) {
    // `timeout`: a FIFO read would otherwise hold the test for ever.
    const auto out = plctest::run_command("timeout 60 " + plctest::bin_dir() + "/" + program + " " +
                                          r.args + " </dev/null");
    EXPECT_EQ(out.exit_code, 2) << program << " " << r.args << "\n" << out.output;
    EXPECT_NE(out.output.find(r.message), std::string::npos) << program << " " << r.args << "\n"
                                                             << out.output;
    EXPECT_EQ(out.output.find("terminate called"), std::string::npos) << out.output;
  }
}

TEST(PlcrunBadInput, AConfigThatIsNoReadableFileIsExitTwo) {
  NotAFile f("bad_config");
  std::vector<Row> rows;
  for (const char* mode : {"--cycles 1", "--list-vars", "--debug"}) {
    rows.push_back({quoted(f.dir()) + " " + mode, f.dir() + ": is a folder, not a file"});
    rows.push_back({quoted(f.fifo()) + " " + mode,
                    f.fifo() + ": is not a regular file (a FIFO): give the file itself"});
    rows.push_back({quoted(f.missing()) + " " + mode, f.missing() + ": cannot open: No such file"});
    rows.push_back({std::string("'' ") + mode, "plcrun: CONFIG is an empty path"});
  }
  expect_exit_two("plcrun", rows);
}

TEST(PlcrunBadInput, AnUnreadableConfigIsExitTwo) {
  Tree t("unreadable");
  const fs::path cfg = t.root() / "cell.yaml";
  Tree::write(cfg, probe_cell("build/libpathprobe.so"));
  ::chmod(cfg.c_str(), 0);
  // root reads any file: run plcrun as nobody then.
  const std::string as =
      ::geteuid() == 0 ? "setpriv --reuid=nobody --regid=nogroup --clear-groups " : "";
  fs::permissions(t.root(), fs::perms::others_exec | fs::perms::others_read, fs::perm_options::add);
  const auto r = plctest::run_command(as + plctest::plcrun_path() + " " + cfg.string() +
                                      " --cycles 1 </dev/null");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(cfg.string() + ": cannot read: Permission denied"), std::string::npos)
      << r.output;
}

TEST(PlcrunBadInput, AFileArgumentThatIsNoFileIsExitTwo) {
  NotAFile f("bad_args");
  const std::string demo = plctest::source_path("programs/demo/cell.yaml");
  expect_exit_two(
      "plcrun",
      {
          {demo + " --commands " + quoted(f.dir()),
           "plcrun: cannot read command file '" + f.dir() + "': is a folder, not a file"},
          {demo + " --commands " + quoted(f.fifo()),
           "plcrun: cannot read command file '" + f.fifo() + "': is not a regular file (a FIFO)"},
          {demo + " --debug --commands ''",
           "plcrun: cannot read command file '': an empty path names no file"},
          {"--new-cell ''", "plcrun: --new-cell: DIR is an empty path"},
      });
}

// With `libraries:` the library is copied into the temporary folder before
// it is loaded: a TMPDIR that names no folder threw filesystem_error.
TEST(PlcrunBadInput, NoTemporaryFolderForTheLibraryIsAConfigError) {
  Tree t("no_tmpdir");
  t.write_config(probe_cell("build/libpathprobe.so"));
  // The config by its absolute path: this is not the bare-name case.
  const std::string cfg = t.config_arg(Ref::Absolute);
  for (const char* mode : {"--cycles 1", "--list-vars"}) {
    const auto r = plctest::run_command("TMPDIR=/nonexistent/tmp " + plctest::plcrun_path() + " " +
                                        cfg + " " + mode + " </dev/null");
    EXPECT_EQ(r.exit_code, 2) << mode << "\n" << r.output;
    EXPECT_NE(r.output.find(cfg + ":2:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("no folder for a temporary copy"), std::string::npos) << r.output;
  }
}

// Whatever a plugin throws for its parameters or devices while the cell is
// built is a config error at its entry (it escaped unless it was a
// ParamError): two plugins of the probe library throw std::runtime_error
// and std::invalid_argument.
TEST(PlcrunBadInput, AnyExceptionOfAPluginsSetUpIsAConfigError) {
  Tree t("refusing_plugins");
  struct Row {
    const char* more;
    const char* message;
  };
  const Row rows[] = {
      {"plugins:\n  - {name: bad, type: refuses_params}\n",
       "cell.yaml:8:5: plugin 'bad': this plugin refuses every configuration"},
      {"plugins:\n  - {name: bad, type: refuses_devices}\n"
       "devices:\n  - {name: dev, plugin: bad}\n",
       "cell.yaml:10:5: device 'dev': this plugin cannot connect any device"},
  };
  for (const Row& row : rows) {
    t.write_config(probe_cell("build/libpathprobe.so", row.more));
    const auto r = t.plcrun(Ref::Absolute, "--list-vars");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(row.message), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("terminate called"), std::string::npos) << r.output;
  }
}

TEST(DnslaveBadInput, AConfigThatIsNoReadableFileIsExitTwo) {
  NotAFile f("dnslave_bad_config");
  expect_exit_two("dnslave", {
                                 {quoted(f.dir()), f.dir() + ": is a folder, not a file"},
                                 {quoted(f.fifo()), f.fifo() + ": is not a regular file (a FIFO)"},
                                 {quoted(f.missing()), f.missing() + ": cannot open: No such file"},
                                 {"''", "an empty path names no file"},
                             });
}

TEST(PndevsimBadInput, AConfigThatIsNoReadableFileIsExitTwo) {
  NotAFile f("pndevsim_bad_config");
  expect_exit_two("pndevsim",
                  {
                      {quoted(f.dir()), f.dir() + ": is a folder, not a file"},
                      {quoted(f.fifo()), f.fifo() + ": is not a regular file (a FIFO)"},
                      {quoted(f.missing()), f.missing() + ": cannot open: No such file"},
                      {"''", "an empty path names no file"},
                  });
}

// The simulator hosts' command line (plc/io/sim_host.hpp): `TOOL
// CONFIG.yaml [--for DURATION]`, anything else a message and exit code 2
// before the config is read. A `--for` without its duration was ignored by
// dnslave and dpslavesim (the run went on without an end).
TEST(SimHostBadInput, CommandLinesOtherThanConfigAndForAreExitTwo) {
  NotAFile f("sim_host_args");
  const std::string cfg = quoted(f.missing());
  for (const char* tool : {"dnslave", "dpslavesim", "pndevsim"}) {
    const std::string t = tool;
    expect_exit_two(tool, {
                              {"", "usage: " + t + " CONFIG.yaml [--for DURATION]"},
                              {cfg + " --for", t + ": --for: needs a duration (e.g. 10s)"},
                              {cfg + " --for soon", t + ": --for: bad duration 'soon'"},
                              {cfg + " --forever 1", t + ": unknown option '--forever'"},
                          });
  }
}

}  // namespace
}  // namespace pathtest
