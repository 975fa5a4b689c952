// Retain start-up says what happened (issue 21, point 4): an explicit warm
// start (--warm) with every copy of the retain file damaged does not start
// the cell (unless --warm-or-cold or `on_damage: cold` allow a cold start);
// the default start falls back to a cold start loudly, in its start-up
// lines and in the summary; a retain file whose folder is missing or not
// writable is a located config error before the cell starts.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>

#include "../runtime/test_helpers.hpp"
#include "plc/retain/retain_manager.hpp"
#include "plc/retain/retain_storage.hpp"

namespace {

using namespace plc;
using retain::OnDamage;
using retain::StartMode;

void damage(const std::string& file) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekg(30);
  char c = 0;
  f.read(&c, 1);
  f.seekp(30);
  c = static_cast<char>(c ^ 0x10);
  f.write(&c, 1);
}

// The policy of docs/config.md ("Retained variables"): --warm-or-cold always
// goes cold; else on_damage; unset, only an explicit --warm stops.
TEST(RetainStart, OnDamagePolicy) {
  using C = RetainOnDamage;
  EXPECT_EQ(retain::on_damage_policy(StartMode::Warm, C::Unset), OnDamage::Stop);
  EXPECT_EQ(retain::on_damage_policy(StartMode::Warm, C::Cold), OnDamage::Cold);
  EXPECT_EQ(retain::on_damage_policy(StartMode::Warm, C::Stop), OnDamage::Stop);
  EXPECT_EQ(retain::on_damage_policy(StartMode::Auto, C::Unset), OnDamage::Cold);
  EXPECT_EQ(retain::on_damage_policy(StartMode::Auto, C::Stop), OnDamage::Stop);
  EXPECT_EQ(retain::on_damage_policy(StartMode::Cold, C::Unset), OnDamage::Cold);
  EXPECT_EQ(retain::on_damage_policy(StartMode::Cold, C::Stop), OnDamage::Stop);
  EXPECT_EQ(retain::on_damage_policy(StartMode::WarmOrCold, C::Stop), OnDamage::Cold);
}

TEST(RetainStart, OnDamageIsColdOrStopAtItsLine) {
  const std::string head = "image: {memory: 16}\ntasks: [{name: m, period: 1ms, programs: []}]\n";
  try {
    parse_cell_config(head + "retain: {file: x, on_damage: later}\n", "c.yaml");
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "c.yaml:3:30: key 'on_damage': 'later' is not cold or stop");
  }
  EXPECT_EQ(parse_cell_config(head + "retain: {file: x, on_damage: stop}\n", "c.yaml")
                .retain.on_damage.value,
            RetainOnDamage::Stop);
  EXPECT_EQ(parse_cell_config(head + "retain: {file: x}\n", "c.yaml").retain.on_damage.value,
            RetainOnDamage::Unset);
}

// The filling cell with a retain section in a folder of its own.
class RetainPlcrunStart : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = plctest::temp_path(::testing::UnitTest::GetInstance()->current_test_info()->name());
    ASSERT_EQ(std::system(("rm -rf " + dir_ + " && mkdir -p " + dir_).c_str()), 0);
  }
  void TearDown() override { std::system(("rm -rf " + dir_).c_str()); }
  // Writes the config with `retain` as its retain: section; its path.
  std::string config(const std::string& retain) {
    const std::string cfg = dir_ + "/cell.yaml";
    std::ofstream(cfg) << base() << "retain: " << retain << "\n";
    return cfg;
  }
  static std::string base() {
    return plctest::read_file(plctest::source_dir() + "/programs/filling_cell/cell.yaml") + "\n";
  }
  plctest::RunResult plcrun(const std::string& cfg, const std::string& args) {
    return plctest::run_command(plctest::plcrun_path() + " " + cfg + " -q " + args);
  }
  // A first life that leaves both copies, then both damaged.
  void both_copies_damaged(const std::string& cfg) {
    const auto first = plcrun(cfg, "--for 1s");
    ASSERT_EQ(first.exit_code, 0) << first.output;
    damage(dir_ + "/filling.retain.a");
    damage(dir_ + "/filling.retain.b");
  }
  std::string dir_;
};

// The operator asked for the retained values: a cold start instead would
// drop them without a word (it printed "every variable at its initial
// value" and exited 0). Now: exit 1, nothing runs, the copies stay as they
// were for whoever repairs them.
TEST_F(RetainPlcrunStart, WarmWithEveryCopyDamagedDoesNotStartTheCell) {
  const std::string cfg = config("{file: filling.retain}");
  both_copies_damaged(cfg);
  const std::string a = plctest::read_file(dir_ + "/filling.retain.a");
  const std::string b = plctest::read_file(dir_ + "/filling.retain.b");
  const auto warm = plcrun(cfg, "--warm --for 1s");
  EXPECT_EQ(warm.exit_code, 1) << warm.output;
  EXPECT_NE(warm.output.find("plcrun: retain: damaged copy " + dir_ + "/filling.retain.a: CRC"),
            std::string::npos)
      << warm.output;
  EXPECT_NE(warm.output.find("plcrun: retain: warm start REFUSED: no valid copy of the retain "
                             "file (all damaged); the cell does not start (plcrun "
                             "--warm-or-cold, or on_damage: cold"),
            std::string::npos)
      << warm.output;
  EXPECT_EQ(warm.output.find("running cell"), std::string::npos) << warm.output;
  EXPECT_EQ(warm.output.find("== summary"), std::string::npos) << warm.output;
  EXPECT_TRUE(plctest::read_file(dir_ + "/filling.retain.a") == a) << "copy .a changed";
  EXPECT_TRUE(plctest::read_file(dir_ + "/filling.retain.b") == b) << "copy .b changed";

  // With an hmi: section (a debugger session without a console) too.
  const std::string hmi_cfg = dir_ + "/hmi.yaml";
  std::ofstream(hmi_cfg) << base()
                         << "retain: {file: filling.retain}\nhmi:\n  url: memq://\n  publish: "
                            "[\"Cell.containers\"]\n";
  const auto hmi = plcrun(hmi_cfg, "--warm --for 1s");
  EXPECT_EQ(hmi.exit_code, 1) << hmi.output;
  EXPECT_NE(hmi.output.find("warm start REFUSED"), std::string::npos) << hmi.output;
  EXPECT_EQ(hmi.output.find("running cell"), std::string::npos) << hmi.output;
  EXPECT_TRUE(plctest::read_file(dir_ + "/filling.retain.a") == a) << "copy .a changed";
}

// Without --warm the start falls back to a cold one, loudly: in the start-up
// lines and as the summary's first line. --warm-or-cold and on_damage: cold
// allow the same; on_damage: stop refuses also without a flag.
TEST_F(RetainPlcrunStart, FallbackToColdIsLoudAndOnlyWhereAllowed) {
  const std::string loud =
      "cold start INSTEAD OF A WARM START: no valid copy of the retain file (all damaged); "
      "every variable at its initial value";
  std::string cfg = config("{file: filling.retain}");
  for (const std::string flags : {"", "--warm-or-cold"}) {
    both_copies_damaged(cfg);
    const auto r = plcrun(cfg, flags + " --for 1s");
    EXPECT_EQ(r.exit_code, 0) << flags << r.output;
    EXPECT_NE(r.output.find("plcrun: retain: " + loud), std::string::npos) << flags << r.output;
    EXPECT_NE(r.output.find("== summary: cell 'filling', virtual time ==\nretain: " + loud),
              std::string::npos)
        << flags << r.output;
  }
  cfg = config("{file: filling.retain, on_damage: cold}");
  both_copies_damaged(cfg);
  auto r = plcrun(cfg, "--warm --for 1s");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("retain: " + loud), std::string::npos) << r.output;

  cfg = config("{file: filling.retain, on_damage: stop}");
  both_copies_damaged(cfg);
  r = plcrun(cfg, "--for 1s");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("plcrun: retain: start REFUSED"), std::string::npos) << r.output;
  r = plcrun(cfg, "--warm-or-cold --for 1s");  // the flag is the operator's explicit choice
  EXPECT_EQ(r.exit_code, 0) << r.output;

  // A healthy start names itself in the summary too.
  r = plcrun(cfg, "--for 1ms");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("retain: warm start from " + dir_ + "/filling.retain."),
            std::string::npos)
      << r.output;

  r = plcrun(cfg, "--warm --warm-or-cold");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--warm, --warm-or-cold, --cold and --reset-retain exclude each other"),
            std::string::npos)
      << r.output;
}

// Before: the cell ran its whole span, every save failed, and only the
// final save said so (exit 1). Now the config is refused at the key, before
// anything starts, with the usual exit code of a config error.
TEST_F(RetainPlcrunStart, FileInAMissingFolderIsALocatedConfigError) {
  const std::string cfg = config("{file: no/such/folder/filling.retain}");
  const auto text = plctest::read_file(cfg);
  const int line = int(std::count(text.begin(), text.begin() + long(text.find("retain: {")), '\n'));
  const auto r = plcrun(cfg, "--for 1s");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(r.output, cfg + ":" + std::to_string(line + 1) + ":16: key 'file': the folder '" +
                          dir_ + "/no/such/folder' does not exist (the retain file '" + dir_ +
                          "/no/such/folder/filling.retain' could never be saved)\n");
  // A file where the folder should be.
  std::ofstream(dir_ + "/plain") << "x";
  const auto f = plcrun(config("{file: plain/filling.retain}"), "--for 1s");
  EXPECT_EQ(f.exit_code, 2) << f.output;
  EXPECT_NE(f.output.find("key 'file': '" + dir_ + "/plain' is not a folder"), std::string::npos)
      << f.output;
}

// A folder this process may not write into. Root may write anywhere, so the
// check runs in a child that drops to nobody (uid/gid 65534) first.
TEST(RetainStorage, FolderNotWritableIsSaidBeforeTheFirstSave) {
  const std::string dir = plctest::temp_path("read_only_folder");
  ASSERT_EQ(std::system(("rm -rf " + dir + " && mkdir -p " + dir).c_str()), 0);
  ASSERT_EQ(::chmod(dir.c_str(), 0555), 0);
  const std::string expect = "the folder '" + dir + "' is not writable (Permission denied)";
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) ::_exit(3);
    ::_exit(retain::Storage(dir + "/cell.retain").check_folder() == expect ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "expected: " << expect;
  ::chmod(dir.c_str(), 0755);
  EXPECT_EQ(retain::Storage(dir + "/cell.retain").check_folder(), "");
  std::system(("rm -rf " + dir).c_str());
}

}  // namespace
