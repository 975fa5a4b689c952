// The HMI bridge over memq:// in virtual time (issue 13): what a client
// sees matches the cell, writes reach the next scan, and everything the
// access rules forbid is refused and counted with nothing applied.
#include <gtest/gtest.h>
#include <sodium.h>
#include <sys/stat.h>

#include <fstream>

#include "hmi_test_cell.hpp"
#include "plc/hmi/command_auth.hpp"
#include "softplc_hmi/command_t.hpp"

using namespace plc;
using plctest::HmiCell;

namespace {

softplc_hmi::command_t command(std::int64_t id, const std::string& verb,
                               std::vector<std::string> args) {
  softplc_hmi::command_t c{};
  c.request_id = id;
  c.client = "test";
  c.verb = verb;
  c.args = std::move(args);
  c.n_args = int(c.args.size());
  c.counter = id;
  return c;
}

std::map<std::string, int> indices(HmiCell& h) {
  std::map<std::string, int> m;
  const auto d = h.bridge->description();
  for (int i = 0; i < d.n; ++i) m[d.vars[std::size_t(i)].path] = i;
  return m;
}

}  // namespace

// Watched values equal what the cell itself shows after the same scan
// (the debugger's read, one scan, never torn), over 300 scans of both tasks.
TEST(HmiBridge, WatchedValuesMatchTheCellAfterEveryScan) {
  HmiCell h;
  const auto idx = indices(h);
  const auto d = h.bridge->description();
  int published = 0;
  for (const auto& v : d.vars) published += v.published;
  EXPECT_GT(published, 10);
  int compared = 0;
  for (int scan = 0; scan < 300; ++scan) {
    ASSERT_TRUE(h.dbg->step(1).ok);
    h.bridge->service();
    for (const auto& v : d.vars) {
      if (!v.published) continue;
      auto it = h.seen.find(idx.at(v.path));
      if (it == h.seen.end()) continue;  // that task has not scanned yet
      // Located variables: the bridge shows the task's view, as print does.
      ASSERT_EQ(it->second, h.value_of(v.path)) << v.path << " after scan " << scan;
      ++compared;
    }
  }
  EXPECT_GT(compared, 300 * 10);
  EXPECT_GT(h.bridge->counters().published, 0U);
}

// A write to a writable variable takes effect at the start of the next
// scan, not before.
TEST(HmiBridge, WriteToWritableVariableTakesEffectAtTheNextScan) {
  HmiCell h;
  h.dbg->step(1);
  const std::string before = h.value_of("Tank.high_level");
  ASSERT_NE(before, "1234");
  const auto r = h.send(command(1, "write", {"Tank.high_level", "1234"}));
  EXPECT_TRUE(r.ok) << r.refusal;
  EXPECT_EQ(r.request_id, 1);
  EXPECT_EQ(h.value_of("Tank.high_level"), before);  // not yet
  h.dbg->step(1, "fast");                            // the next scan of Tank's task
  EXPECT_EQ(h.value_of("Tank.high_level"), "1234");
  EXPECT_EQ(h.bridge->counters().commands, 1U);
}

// Everything the access rules forbid is refused with a reason, counted,
// and changes nothing.
TEST(HmiBridge, WritesOutsideTheWritablePatternsAreRefusedAndNothingApplied) {
  HmiCell h;
  h.dbg->step(1);
  const std::string step = h.value_of("Tank.step");
  auto r = h.send(command(1, "write", {"Tank.step", "7"}));
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.refusal.find("not allowed"), std::string::npos) << r.refusal;
  r = h.send(command(2, "force", {"Tank.high_level", "5"}));  // writable, not forceable
  EXPECT_FALSE(r.ok);
  r = h.send(command(3, "write", {"Tank.hold.running_", "TRUE"}));  // read-only, pattern-less
  EXPECT_FALSE(r.ok);
  r = h.send(command(4, "pause", {}));  // stop_commands: false
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.refusal.find("stop_commands"), std::string::npos) << r.refusal;
  r = h.send(command(5, "write", {"Tank.high_level", "not-a-number"}));  // the debugger says no
  EXPECT_FALSE(r.ok);
  r = h.send(command(6, "frobnicate", {}));
  EXPECT_FALSE(r.ok);
  h.dbg->step(2);
  EXPECT_EQ(h.value_of("Tank.step"), step);
  EXPECT_EQ(h.dbg->execute("forces"), "no forces\n");
  EXPECT_EQ(h.bridge->counters().refused, 6U);
  EXPECT_EQ(h.bridge->counters().commands, 0U);
}

// Malformed messages (not a command_t, truncated, wrong fingerprint) are
// counted and get no reply.
TEST(HmiBridge, MalformedCommandsAreCountedAndIgnored) {
  HmiCell h;
  const std::uint8_t junk[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  h.bridge->transport().publish(h.bridge->channels().cmd, junk, sizeof junk);
  auto c = command(1, "write", {"Tank.high_level", "99"});
  std::vector<std::uint8_t> buf(std::size_t(c.getEncodedSize()));
  c.encode(buf.data(), 0, int(buf.size()));
  h.bridge->transport().publish(h.bridge->channels().cmd, buf.data(), unsigned(buf.size() - 3));
  // An argument count of -1 and of 2^31-1 with no arguments behind it:
  // lcm-gen's decoder would resize its vector to that count first
  // (std::length_error, or gigabytes).
  for (std::uint32_t n : {0xFFFFFFFFU, 0x7FFFFFFFU}) {
    auto bad = command(2, "read", {});
    std::vector<std::uint8_t> b(std::size_t(bad.getEncodedSize()));
    bad.encode(b.data(), 0, int(b.size()));
    const std::size_t at = b.size() - 16 - 8 - 32 - 4;  // n_args before epoch, counter, tag
    for (int k = 0; k < 4; ++k) b[at + std::size_t(k)] = std::uint8_t(n >> (24 - 8 * k));
    h.bridge->transport().publish(h.bridge->channels().cmd, b.data(), unsigned(b.size()));
  }
  h.replies.clear();
  h.bridge->service();
  EXPECT_TRUE(h.replies.empty());
  EXPECT_EQ(h.bridge->counters().malformed, 4U);
  h.dbg->step(1);
  EXPECT_NE(h.value_of("Tank.high_level"), "99");
}

// The shared key: a command without a right tag, or with a counter not above
// the last accepted one, is refused and counted; nothing is applied.
TEST(HmiBridge, SharedKeyRefusesBadTagsAndReplays) {
  ASSERT_GE(sodium_init(), 0);
  const std::string key_file = ::testing::TempDir() + "hmi_test.key";
  std::ofstream(key_file) << "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f\n";
  ::chmod(key_file.c_str(), 0600);
  HmiCell h(plctest::kHmiSection, key_file);
  std::string err;
  const auto key = hmi::load_key(key_file, err);
  ASSERT_TRUE(key) << err;
  h.dbg->step(1);
  // As a client signs after reading the description (test_hmi_auth.cpp).
  const hmi::TagContext ctx{"PLC", "demo", h.bridge->channels().cmd};
  auto sign = [&](softplc_hmi::command_t& c) {
    hmi::set_epoch(c, h.bridge->epoch());
    hmi::sign(c, *key, ctx);
  };

  auto unsigned_cmd = command(10, "write", {"Tank.high_level", "111"});
  EXPECT_FALSE(h.send(unsigned_cmd).ok);
  EXPECT_EQ(h.bridge->counters().bad_tag, 1U);

  auto first = command(11, "write", {"Tank.high_level", "222"});
  sign(first);
  auto tampered = first;
  tampered.args[1] = "333";  // the tag no longer fits
  EXPECT_FALSE(h.send(tampered).ok);
  EXPECT_EQ(h.bridge->counters().bad_tag, 2U);

  EXPECT_TRUE(h.send(first).ok);
  h.dbg->step(1, "fast");
  EXPECT_EQ(h.value_of("Tank.high_level"), "222");

  auto second = command(12, "write", {"Tank.high_level", "444"});
  sign(second);
  EXPECT_TRUE(h.send(second).ok);
  h.dbg->step(1, "fast");
  EXPECT_EQ(h.value_of("Tank.high_level"), "444");

  const auto replay = h.send(first);  // a captured, correctly signed old command
  EXPECT_FALSE(replay.ok);
  EXPECT_NE(replay.refusal.find("replayed"), std::string::npos) << replay.refusal;
  h.dbg->step(1);
  EXPECT_EQ(h.value_of("Tank.high_level"), "444");
  EXPECT_EQ(h.bridge->counters().replayed, 1U);
  EXPECT_EQ(h.bridge->counters().commands, 2U);
}

// The typed API through the bridge: read, force/unforce and, when the cell
// allows stopping commands, step and breakpoints.
TEST(HmiBridge, ReadForceAndStopCommandsWhenAllowed) {
  HmiCell h(std::string(plctest::kHmiSection) + "  stop_commands: true\n");
  h.dbg->step(1);
  auto r = h.send(command(1, "read", {"Tank.level", "Nope.x"}));
  ASSERT_TRUE(r.ok);
  ASSERT_EQ(r.n, 2);
  EXPECT_EQ(r.values[0].text, h.value_of("Tank.level"));
  EXPECT_EQ(r.values[0].type, "INT");
  EXPECT_EQ(r.values[0].address, "%IW0");
  EXPECT_NE(r.values[1].error.find("unknown variable"), std::string::npos);
  EXPECT_TRUE(h.send(command(2, "force", {"Tank.enable", "FALSE"})).ok);
  h.dbg->step(3);
  EXPECT_EQ(h.value_of("Tank.enable"), "FALSE");
  EXPECT_TRUE(h.dbg->read({"Tank.enable"}).front().forced);
  EXPECT_TRUE(h.send(command(3, "unforce", {"Tank.enable"})).ok);
  EXPECT_FALSE(h.dbg->read({"Tank.enable"}).front().forced);
  const auto scans = h.dbg->scan_count();
  EXPECT_TRUE(h.send(command(4, "step", {"5"})).ok);
  EXPECT_EQ(h.dbg->scan_count(), scans + 5);
  r = h.send(command(5, "break", {"Tank.step = 3"}));
  EXPECT_TRUE(r.ok) << r.refusal;
  EXPECT_NE(h.dbg->execute("breaks").find("Tank.step = 3"), std::string::npos);
  EXPECT_TRUE(h.send(command(6, "delete", {"all"})).ok);
  EXPECT_FALSE(h.send(command(7, "step", {"0"})).ok);
}

// The hmi: section's errors carry file:line:col like the rest of the config.
TEST(HmiConfig, ErrorsAreLocated) {
  const std::string base = plctest::demo_yaml();
  auto error_of = [&](const std::string& hmi) -> std::string {
    try {
      HmiCell h(hmi);
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(error_of("\nhmi:\n  rate: 5000\n").find("hmi_test.yaml:"), std::string::npos);
  EXPECT_NE(error_of("\nhmi:\n  rate: 5000\n").find("rate"), std::string::npos);
  EXPECT_NE(error_of("\nhmi:\n  colour: red\n").find("colour"), std::string::npos);
  EXPECT_NE(error_of("\nhmi:\n  url: http://x\n").find("not an LCM url"), std::string::npos);
  const std::string nomatch = error_of("\nhmi:\n  url: memq://\n  publish: [\"Nope.*\"]\n");
  EXPECT_NE(nomatch.find("matches no variable"), std::string::npos) << nomatch;
  // The pattern's own line and column.
  const int line = int(std::count(base.begin(), base.end(), '\n')) + 4;
  EXPECT_NE(nomatch.find(":" + std::to_string(line) + ":"), std::string::npos) << nomatch;
  EXPECT_NE(error_of("\nhmi:\n  url: memq://\n  key_file: /nonexistent.key\n").find("key_file"),
            std::string::npos);
  const auto cfg = parse_cell_config(base + "\nhmi:\n  url: memq://\n", "x.yaml");
  EXPECT_TRUE(cfg.hmi.present);
  EXPECT_EQ(cfg.hmi.rate.value, 10);
  EXPECT_FALSE(cfg.hmi.stop_commands.value);
  EXPECT_EQ(parse_cell_config(base, "x.yaml").hmi.url.value, kDefaultHmiUrl);
}

// Issue 21 point 6: an index in a pattern is written as --list-vars prints
// it. Patterns used to go to fnmatch(3) as they were, which reads `[0]` as
// a set of one character: `S.arr[1]` matched "S.arr1" and no variable,
// and only the undocumented `S.arr\[1\]` worked (it still does).
TEST(HmiConfig, PatternWithAnIndexMatchesThePathListVarsPrints) {
  EXPECT_TRUE(hmi::pattern_matches("S.arr[1]", "S.arr[1]"));
  EXPECT_FALSE(hmi::pattern_matches("S.arr[1]", "S.arr1"));
  EXPECT_FALSE(hmi::pattern_matches("S.arr[12]", "S.arr[1]"));
  EXPECT_TRUE(hmi::pattern_matches("S.arr[*]", "S.arr[12]"));
  EXPECT_TRUE(hmi::pattern_matches("S.arr[?]", "S.arr[2]"));
  EXPECT_TRUE(hmi::pattern_matches("S.arr\\[1\\]", "S.arr[1]"));
  EXPECT_TRUE(hmi::pattern_matches("Tank.*", "Tank.hold.ET"));
  // Shapes (tests/runtime/test_programs.hpp) has `arr` (INT[3]) and
  // `inner.timers` (TON[2]).
  const std::string cell =
      "cell: shapes\ntasks: [{name: m, period: 1ms, programs: [S]}]\n"
      "programs: [{name: S, type: Shapes}]\n";
  HmiCell h(
      "\nhmi:\n  url: memq://\n  publish: [\"S.arr[1]\", \"S.inner.timers[0].*\"]\n"
      "  writable: [\"S.arr[2]\"]\n",
      "", cell);
  std::map<std::string, softplc_hmi::var_desc_t> d;
  for (const auto& v : h.bridge->description().vars) d[v.path] = v;
  ASSERT_EQ(d.count("S.arr[1]"), 1U);
  EXPECT_TRUE(d["S.arr[1]"].published);
  EXPECT_FALSE(d["S.arr[0]"].published);
  EXPECT_FALSE(d["S.arr[1]"].writable);
  EXPECT_TRUE(d["S.arr[2]"].writable);
  EXPECT_TRUE(d["S.inner.timers[0].ET"].published);
  EXPECT_FALSE(d["S.inner.timers[1].ET"].published);
}
