// Issue 22: commands authenticated both ways and bound to their context
// (hmi-bridge/README.md, "Authentication"). memq:// in virtual time: a
// signed command replayed after the bridge started again, or to a second
// cell with the same key, is refused; a tag made for another prefix, cell,
// channel or epoch is refused; replies and the description are signed and
// plcctl's client takes only the real reply; `unforce all` from a client
// releases only what it may force; key files others may read are refused.
#include <gtest/gtest.h>
#include <sodium.h>
#include <sys/stat.h>

#include <fstream>

#include "client.hpp"
#include "hmi_test_cell.hpp"
#include "plc/hmi/command_auth.hpp"
#include "runtime/test_helpers.hpp"
#include "softplc_hmi/command_t.hpp"

using namespace plc;
using plctest::HmiCell;

namespace {

constexpr const char* kKeyHex = "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f";

std::string key_file(const std::string& name, mode_t mode, const std::string& text = kKeyHex) {
  const std::string path = ::testing::TempDir() + "hmi_auth_" + name + ".key";
  ::unlink(path.c_str());
  std::ofstream(path) << text << "\n";
  ::chmod(path.c_str(), mode);
  return path;
}

hmi::Key the_key() {
  std::string err;
  const auto k = hmi::load_key(key_file("load", 0600), err);
  EXPECT_TRUE(k) << err;
  return k.value_or(hmi::Key{});
}

softplc_hmi::command_t command(std::int64_t counter, const std::string& verb,
                               std::vector<std::string> args) {
  softplc_hmi::command_t c{};
  c.request_id = counter;
  c.client = "test";
  c.verb = verb;
  c.args = std::move(args);
  c.n_args = int(c.args.size());
  c.counter = counter;
  return c;
}

// Signed as a client that read h's description would sign it.
softplc_hmi::command_t signed_for(HmiCell& h, softplc_hmi::command_t c, const hmi::Key& key) {
  const auto d = h.bridge->description();
  hmi::set_epoch(c, hmi::epoch_of(d));
  hmi::sign(c, key, {"PLC", d.cell, h.bridge->channels().cmd});
  return c;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The demo cell under another name (a second cell on the same bus).
std::string demo_named(const std::string& name) {
  std::string yaml = plctest::demo_yaml();
  const auto at = yaml.find("cell: demo\n");
  EXPECT_NE(at, std::string::npos);
  if (at != std::string::npos) yaml.replace(at, 11, "cell: " + name + "\n");
  return yaml;
}

}  // namespace

// A signed command captured (lcm-logger) and replayed after the bridge
// started again - plcrun restarted, or the bridge's process - carries the
// old epoch: refused as stale, counted, nothing applied. Before issue 22
// the replay guard lived in memory only and the new bridge applied it.
TEST(HmiAuth, SignedCommandReplayedAfterARestartIsRefusedAsStale) {
  const std::string kf = key_file("restart", 0600);
  const hmi::Key key = the_key();
  auto first = std::make_unique<HmiCell>(plctest::kHmiSection, kf);
  first->dbg->step(1);
  const auto captured = signed_for(*first, command(1000, "write", {"Tank.high_level", "222"}), key);
  EXPECT_TRUE(first->send(captured).ok);
  const hmi::Epoch old_epoch = first->bridge->epoch();
  first.reset();

  HmiCell again(plctest::kHmiSection, kf);
  EXPECT_NE(again.bridge->epoch(), old_epoch);
  again.dbg->step(1);
  const std::string before = again.value_of("Tank.high_level");
  ASSERT_NE(before, "222");
  const auto r = again.send(captured);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(has(r.refusal, "stale epoch")) << r.refusal;
  // The signed refusal names the epoch to use (plcctl sends again for it).
  EXPECT_EQ(hmi::epoch_of(r), again.bridge->epoch());
  again.dbg->step(2);
  EXPECT_EQ(again.value_of("Tank.high_level"), before);
  EXPECT_EQ(again.bridge->counters().stale, 1U);
  EXPECT_EQ(again.bridge->counters().commands, 0U);
}

// A rebuild of the runtime in the same process (the debugger's restart or
// goto) keeps the bridge, its epoch and its counters: a command signed
// before is still a replay after it, a new one is served.
TEST(HmiAuth, RestartInsideTheSessionKeepsTheEpochAndTheReplayGuard) {
  const std::string kf = key_file("rebuild", 0600);
  const hmi::Key key = the_key();
  HmiCell h(plctest::kHmiSection, kf);
  h.dbg->step(1);
  const auto first = signed_for(h, command(10, "write", {"Tank.high_level", "333"}), key);
  EXPECT_TRUE(h.send(first).ok);
  const hmi::Epoch epoch = h.bridge->epoch();
  const std::string restarted = h.dbg->execute("restart cold");  // a new runtime, attached again
  ASSERT_TRUE(has(restarted, "cold restart")) << restarted;
  EXPECT_EQ(h.bridge->epoch(), epoch);
  EXPECT_EQ(hmi::epoch_of(h.bridge->description()), epoch);
  const auto r = h.send(first);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(has(r.refusal, "replayed")) << r.refusal;
  EXPECT_TRUE(h.send(signed_for(h, command(11, "write", {"Tank.high_level", "444"}), key)).ok);
  h.dbg->step(1, "fast");
  EXPECT_EQ(h.value_of("Tank.high_level"), "444");
}

// Two cells on one bus with the same key and prefix: what is signed for
// one does not verify on the other, even with the other's epoch (the tag
// binds the cell's name too).
TEST(HmiAuth, SignedCommandReplayedToASecondCellWithTheSameKeyIsRefused) {
  const std::string kf = key_file("two_cells", 0600);
  const hmi::Key key = the_key();
  HmiCell a(plctest::kHmiSection, kf);
  HmiCell b(plctest::kHmiSection, kf, demo_named("demo2"));
  a.dbg->step(1);
  b.dbg->step(1);
  const std::string before = b.value_of("Tank.high_level");
  const auto for_a = signed_for(a, command(20, "write", {"Tank.high_level", "555"}), key);
  EXPECT_TRUE(a.send(for_a).ok);
  auto r = b.send(for_a);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(has(r.refusal, "bad tag")) << r.refusal;
  // b's epoch, a's cell name: still not b's.
  auto c = command(21, "write", {"Tank.high_level", "556"});
  hmi::set_epoch(c, b.bridge->epoch());
  hmi::sign(c, key, {"PLC", "demo", "PLC_CMD"});
  r = b.send(c);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(has(r.refusal, "bad tag")) << r.refusal;
  b.dbg->step(2);
  EXPECT_EQ(b.value_of("Tank.high_level"), before);
  EXPECT_EQ(b.bridge->counters().bad_tag, 2U);
  EXPECT_EQ(b.bridge->counters().commands, 0U);
}

// Each part of the context, changed on its own, makes the tag fail; the
// epoch field changed after signing too; a right tag for another epoch is
// stale. Only the command signed for exactly this context is applied.
TEST(HmiAuth, TagMadeForAnotherPrefixCellChannelOrEpochIsRefused) {
  const std::string kf = key_file("context", 0600);
  const hmi::Key key = the_key();
  HmiCell h(plctest::kHmiSection, kf);
  h.dbg->step(1);
  const hmi::Epoch epoch = h.bridge->epoch();
  std::int64_t counter = 100;
  auto signed_with = [&](const hmi::TagContext& ctx, const hmi::Epoch& e) {
    ++counter;
    auto c = command(counter, "write", {"Tank.high_level", std::to_string(counter)});
    hmi::set_epoch(c, e);
    hmi::sign(c, key, ctx);
    return c;
  };
  for (const hmi::TagContext& ctx :
       {hmi::TagContext{"PLC2", "demo", "PLC_CMD"}, hmi::TagContext{"PLC", "other", "PLC_CMD"},
        hmi::TagContext{"PLC", "demo", "PLC_REPLY"}, hmi::TagContext{"PLC", "demo", "PLC2_CMD"}}) {
    const auto r = h.send(signed_with(ctx, epoch));
    EXPECT_FALSE(r.ok) << ctx.prefix << " " << ctx.cell << " " << ctx.channel;
    EXPECT_TRUE(has(r.refusal, "bad tag")) << r.refusal;
  }
  auto moved = signed_with({"PLC", "demo", "PLC_CMD"}, epoch);
  moved.epoch[0] = std::int8_t(moved.epoch[0] ^ 1);  // the tag covers the epoch
  EXPECT_TRUE(has(h.send(moved).refusal, "bad tag"));
  hmi::Epoch other = epoch;
  other[15] = std::uint8_t(other[15] ^ 0x80);
  EXPECT_TRUE(has(h.send(signed_with({"PLC", "demo", "PLC_CMD"}, other)).refusal, "stale epoch"));
  const auto c = h.bridge->counters();
  EXPECT_EQ(c.bad_tag, 5U);
  EXPECT_EQ(c.stale, 1U);
  EXPECT_EQ(c.commands, 0U);
  h.dbg->step(1, "fast");
  EXPECT_NE(h.value_of("Tank.high_level"), std::to_string(counter));
  EXPECT_TRUE(h.send(signed_with({"PLC", "demo", "PLC_CMD"}, epoch)).ok);
  h.dbg->step(1, "fast");
  EXPECT_EQ(h.value_of("Tank.high_level"), std::to_string(counter));
}

// describe needs no tag (it is how a client learns the epoch) and changes
// nothing; what it publishes, and every reply, refusals included, is
// signed for this prefix, cell, channel and epoch.
TEST(HmiAuth, DescriptionAndRepliesAreSigned) {
  const std::string kf = key_file("replies", 0600);
  const hmi::Key key = the_key();
  HmiCell h(plctest::kHmiSection, kf);
  const auto d = h.bridge->description();
  EXPECT_TRUE(d.key_required);
  EXPECT_EQ(hmi::epoch_of(d), h.bridge->epoch());
  EXPECT_TRUE(hmi::verify(d, key, {"PLC", "demo", "PLC_DESC"}));
  EXPECT_FALSE(hmi::verify(d, key, {"PLC", "demo", "PLC_REPLY"}));
  auto forged = d;
  forged.vars[0].writable = !forged.vars[0].writable;
  EXPECT_FALSE(hmi::verify(forged, key, {"PLC", "demo", "PLC_DESC"}));

  const auto described = h.send(command(1, "describe", {}));
  EXPECT_TRUE(described.ok) << described.refusal;
  const auto refused = h.send(command(2, "write", {"Tank.high_level", "1"}));  // unsigned
  EXPECT_FALSE(refused.ok);
  const auto served = h.send(signed_for(h, command(3, "read", {"Tank.level"}), key));
  EXPECT_TRUE(served.ok) << served.refusal;
  for (const auto& r : {described, refused, served}) {
    EXPECT_EQ(hmi::epoch_of(r), h.bridge->epoch());
    EXPECT_TRUE(hmi::verify(r, key, {"PLC", "demo", "PLC_REPLY"})) << r.request_id;
  }
  auto changed = served;
  changed.values[0].text = "12345";
  EXPECT_FALSE(hmi::verify(changed, key, {"PLC", "demo", "PLC_REPLY"}));
  EXPECT_EQ(h.bridge->counters().commands, 1U);
}

// plcctl's client with a key (issue 22: it printed values from forged
// reply_t messages): it learns the epoch only from a description whose tag
// verifies and takes as the answer only the signed reply to its own
// request. Unsigned, forged (another key), mis-addressed (another request,
// another client) and wrongly bound (another cell) replies that come first
// are passed over; with nothing but those it reports no reply, exit 1.
TEST(HmiAuth, PlcctlClientRefusesUnsignedForgedAndMisaddressedReplies) {
  const std::string kf = key_file("client", 0600);
  const hmi::Key key = the_key();
  hmi::Key wrong = key;
  wrong[0] ^= 1;
  HmiCell h(plctest::kHmiSection, kf);
  h.dbg->step(1);
  hmi::Client client("memq://", "PLC", key, std::chrono::milliseconds(300));
  bool answer = true;  // the bridge's real reply comes last, or not at all
  int commands_seen = 0;
  client.on_sent = [&](const softplc_hmi::command_t& c) {
    ++commands_seen;
    hmi::Transport& bus = client.transport();
    if (c.verb == "describe") {
      auto d = h.bridge->description();
      auto unsigned_d = d;
      std::fill(std::begin(unsigned_d.tag), std::end(unsigned_d.tag), std::int8_t(0));
      auto forged_d = d;
      forged_d.vars[0].writable = true;
      hmi::sign(forged_d, wrong, {"PLC", "demo", "PLC_DESC"});
      bus.publish("PLC_DESC", &unsigned_d);
      bus.publish("PLC_DESC", &forged_d);
      bus.publish("PLC_DESC", &d);
      return;
    }
    // The bridge serves the command the client signed.
    std::vector<std::uint8_t> bytes(std::size_t(c.getEncodedSize()));
    c.encode(bytes.data(), 0, int(bytes.size()));
    h.replies.clear();
    h.bridge->on_command_bytes(bytes.data(), bytes.size());
    h.bridge->service();
    ASSERT_EQ(h.replies.size(), 1U);
    const softplc_hmi::reply_t real = h.replies.front();
    EXPECT_TRUE(real.ok) << real.refusal;
    auto fake = real;
    fake.values[0].text = "31337";
    fake.text = "forged";
    auto unsigned_r = fake;
    std::fill(std::begin(unsigned_r.tag), std::end(unsigned_r.tag), std::int8_t(0));
    auto other_key = fake;
    hmi::sign(other_key, wrong, {"PLC", "demo", "PLC_REPLY"});
    auto other_cell = fake;
    hmi::sign(other_cell, key, {"PLC", "demo2", "PLC_REPLY"});
    auto other_request = fake;
    other_request.request_id ^= 1;
    hmi::sign(other_request, key, {"PLC", "demo", "PLC_REPLY"});
    auto other_client = fake;
    other_client.client = "someone-else";
    hmi::sign(other_client, key, {"PLC", "demo", "PLC_REPLY"});
    for (const auto* r : {&unsigned_r, &other_key, &other_cell, &other_request, &other_client})
      bus.publish("PLC_REPLY", r);
    if (answer) bus.publish("PLC_REPLY", &real);
  };
  std::string err;
  auto r = client.command("read", {"Tank.level"}, err);
  ASSERT_TRUE(r) << err;
  EXPECT_TRUE(r->ok) << r->refusal;
  ASSERT_EQ(r->values.size(), 1U);
  EXPECT_EQ(r->values[0].text, h.value_of("Tank.level"));
  EXPECT_NE(r->text, "forged");
  EXPECT_EQ(commands_seen, 2);  // describe, read

  answer = false;
  r = client.command("read", {"Tank.level"}, err);
  EXPECT_FALSE(r) << r->text;
  EXPECT_TRUE(has(err, "3 replies to this request refused")) << err;
}

// The signed "stale epoch" refusal gives plcctl's client the epoch to use:
// a client that learnt the epoch of an earlier bridge sends once more.
TEST(HmiAuth, PlcctlClientSendsAgainForTheEpochOfAStaleRefusal) {
  const std::string kf = key_file("client_stale", 0600);
  const hmi::Key key = the_key();
  auto old_bridge = std::make_unique<HmiCell>(plctest::kHmiSection, kf);
  HmiCell h(plctest::kHmiSection, kf);
  h.dbg->step(1);
  hmi::Client client("memq://", "PLC", key, std::chrono::milliseconds(300));
  int reads = 0;
  client.on_sent = [&](const softplc_hmi::command_t& c) {
    if (c.verb == "describe") {  // the description of the bridge that was
      auto d = old_bridge->bridge->description();
      client.transport().publish("PLC_DESC", &d);
      return;
    }
    ++reads;
    std::vector<std::uint8_t> bytes(std::size_t(c.getEncodedSize()));
    c.encode(bytes.data(), 0, int(bytes.size()));
    h.replies.clear();
    h.bridge->on_command_bytes(bytes.data(), bytes.size());
    h.bridge->service();
    ASSERT_EQ(h.replies.size(), 1U);
    client.transport().publish("PLC_REPLY", &h.replies.front());
  };
  std::string err;
  const auto r = client.command("read", {"Tank.level"}, err);
  ASSERT_TRUE(r) << err;
  EXPECT_TRUE(r->ok) << r->refusal;
  EXPECT_EQ(reads, 2);
  EXPECT_EQ(h.bridge->counters().stale, 1U);
  EXPECT_EQ(h.bridge->counters().commands, 1U);
}

// Issue 22: `unforce all restore` from a client released the console's
// forces too (the forceable check was skipped for "all"). Now it releases,
// in one step, only the forces the forceable patterns match and reports
// the others as kept; those stay, with their values.
TEST(HmiAuth, UnforceAllFromTheHmiReleasesOnlyWhatItMayForce) {
  HmiCell h;
  h.dbg->step(1);
  const std::string enable_before = h.value_of("Tank.enable");
  ASSERT_TRUE(h.dbg->force("Tank.step", "3").ok);  // the console's
  ASSERT_TRUE(h.dbg->force("%QW0", "16#1234").ok);
  auto r = h.send(command(1, "force", {"Tank.enable", "FALSE"}));
  ASSERT_TRUE(r.ok) << r.refusal;
  h.dbg->step(2);
  r = h.send(command(2, "unforce", {"all", "restore"}));
  EXPECT_TRUE(r.ok) << r.refusal;
  EXPECT_TRUE(has(r.text, "unforced Tank.enable, restoring " + enable_before)) << r.text;
  EXPECT_TRUE(has(r.text, "kept Tank.step")) << r.text;
  EXPECT_TRUE(has(r.text, "kept %QW0")) << r.text;
  h.dbg->step(3);
  EXPECT_EQ(h.value_of("Tank.step"), "3");
  EXPECT_TRUE(h.dbg->read({"Tank.step"}).front().forced);
  EXPECT_EQ(h.value_of("%QW0"), "16#1234");
  EXPECT_FALSE(h.dbg->read({"Tank.enable"}).front().forced);
  const std::string forces = h.dbg->execute("forces");
  EXPECT_TRUE(has(forces, "Tank.step := 3")) << forces;
  EXPECT_FALSE(has(forces, "Tank.enable")) << forces;
  // Nothing left that the client may release: refused, the rest kept.
  r = h.send(command(3, "unforce", {"all"}));
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(has(r.refusal, "kept Tank.step")) << r.refusal;
  EXPECT_TRUE(h.dbg->read({"Tank.step"}).front().forced);
  // The console's own `unforce all` still releases everything.
  EXPECT_TRUE(h.dbg->unforce("all", false).ok);
  EXPECT_EQ(h.dbg->execute("forces"), "no forces\n");
}

// A key file that group or others may read or write, or that is not a
// regular file of 64 hex digits, is refused: a located config error for the
// bridge, exit 2 with the reason for plcctl. 0600 and 0400 are accepted.
TEST(HmiAuth, KeyFileOthersMayReadIsRefused) {
  auto error_of = [](const std::string& path) -> std::string {
    try {
      HmiCell h(plctest::kHmiSection, path);
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  };
  const std::string open_key = key_file("mode0644", 0644);
  std::string e = error_of(open_key);
  EXPECT_TRUE(has(e, "hmi_test.yaml:")) << e;
  EXPECT_TRUE(has(e, "key_file")) << e;
  EXPECT_TRUE(has(e, "readable or writable by group or others (mode 0644)")) << e;
  EXPECT_TRUE(has(e, "chmod 600")) << e;
  EXPECT_TRUE(has(error_of(key_file("mode0640", 0640)), "mode 0640"));
  EXPECT_TRUE(has(error_of(key_file("mode0602", 0602)), "mode 0602"));
  EXPECT_TRUE(has(error_of(::testing::TempDir()), "not a regular file"));
  EXPECT_TRUE(has(error_of(key_file("short", 0600, "0011")), "64 hex digits"));
  EXPECT_TRUE(has(error_of(key_file("long", 0600, std::string(kKeyHex) + "00")), "64 hex digits"));
  EXPECT_TRUE(has(error_of(key_file("nothex", 0600, std::string(64, 'g'))), "64 hex digits"));
  // Larger than 4,096 bytes: refused unread; spaces around the digits are fine.
  EXPECT_TRUE(has(error_of(key_file("huge", 0600, std::string(kKeyHex) + std::string(5000, ' '))),
                  "bytes: a key file holds 64 hex digits"));
  EXPECT_EQ(error_of(key_file("spaced", 0600, "  " + std::string(kKeyHex) + "\n\n")), "");
  EXPECT_EQ(error_of(key_file("mode0600", 0600)), "");
  EXPECT_EQ(error_of(key_file("mode0400", 0400)), "");

  const auto run = plctest::run_command(plctest::bin_dir() + "/plcctl --key " + open_key +
                                        " --url memq:// --timeout 10 read Tank.level");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_TRUE(has(run.output, "--key: key file")) << run.output;
  EXPECT_TRUE(has(run.output, "mode 0644")) << run.output;
}

// Within an epoch the guard tracks at most kMaxClients clients; the one it
// forgets leaves a floor behind, so none of its commands becomes fresh.
TEST(HmiAuth, ReplayGuardForgetsTheLowestClientBehindAFloor) {
  using V = hmi::ReplayGuard::Verdict;
  hmi::ReplayGuard g;
  for (std::size_t i = 0; i < hmi::ReplayGuard::kMaxClients; ++i) {
    const std::string client = "c" + std::to_string(i);
    const std::int64_t counter = 1000 + std::int64_t(i) * 10;
    ASSERT_EQ(g.check(client, counter), V::fresh);
    g.accept(client, counter);
  }
  EXPECT_EQ(g.check("c0", 1000), V::replayed);
  EXPECT_EQ(g.check("c0", 999), V::replayed);
  EXPECT_EQ(g.check("c0", 1001), V::fresh);
  g.accept("new", 5000);  // full: c0 (counter 1000, the lowest) is forgotten
  EXPECT_EQ(g.clients(), hmi::ReplayGuard::kMaxClients);
  EXPECT_EQ(g.floor(), 1000);
  EXPECT_EQ(g.check("c0", 1000), V::below_floor);  // its captures stay refused
  EXPECT_EQ(g.check("c0", 1001), V::fresh);
  EXPECT_EQ(g.check("c1", 1010), V::replayed);  // still tracked
  EXPECT_EQ(g.check("new", 5000), V::replayed);
}
