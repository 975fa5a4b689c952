// Handshake faults that a healthy device never shows, scripted byte by byte
// on a bare window: each must end as its ErrorID (README table), never as
// a block that waits for ever.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstring>
#include <string_view>
#include <type_traits>
#include <vector>

#include "plc/fb/weighing/command.hpp"
#include "plc/fb/weighing/write_value.hpp"

namespace wg = plc::weighing;
namespace eid = plc::weighing::error_id;
using namespace std::chrono_literals;

namespace {

// A PR5510_Device on raw buffers; the test plays the device.
struct Scripted {
  Scripted() {
    link.set_state(plc::io::DeviceState::Online);
    dev.port.bind(in, out, &link);
    dev.WriteTimeout = 1s;
  }
  template <class F>
  void scan(F&& body) {
    ctx.now += 1ms;
    if (echo) in[wg::r::kReadValueSelected] = out[wg::w::kReadValueSelect];
    dev(ctx);
    body();
  }
  bool echo = true;  // answer every read code at once
  std::array<std::uint8_t, 8> in{}, out{};
  plc::io::DeviceLink link;
  wg::PR5510_Device dev;
  plc::ScanContext ctx{};
};

template <class FB>
std::uint16_t run_to_error(Scripted& s, FB& fb, std::chrono::milliseconds limit) {
  fb.Device = &s.dev;
  fb.Execute = true;
  for (std::int64_t i = 0; i < limit.count() && !fb.Done && !fb.Error; ++i)
    s.scan([&] { fb(s.ctx); });
  EXPECT_TRUE(fb.Error);
  return fb.ErrorID;
}

}  // namespace

// The device block's steady read path (the holder alone requests its
// code, echoed, no read error) against the general arbitration
// (scan_general()): two devices fed the same requests and window bytes
// over a random walk of clients coming and going, urgent and normal
// requests, new codes, missing and wrong echoes, echo timeouts, status
// changes and off-line scans write the same window bytes and end every
// scan in the same state (every reflected field but the port). Fails with
// any step of the steady path left out (e.g. holder_served_).
struct DeviceStateBytes {
  std::vector<std::uint8_t> bytes;
  template <class T>
  void operator()(const char* name, T& v) {
    if (std::string_view(name) == "port") return;
    if constexpr (std::is_trivially_copyable_v<T>) {
      std::uint8_t b[sizeof(T)];
      std::memcpy(b, &v, sizeof(T));
      bytes.insert(bytes.end(), b, b + sizeof(T));
    } else {
      ADD_FAILURE() << name << " is not compared";
    }
  }
};
std::vector<std::uint8_t> device_state(wg::PR5510_Device& d) {
  DeviceStateBytes s;
  d.reflect(s);
  return s.bytes;
}

TEST(Pr5510Faults, ReadPathsAgree) {
  Scripted a, b;
  a.echo = b.echo = false;  // the walk plays the echo
  a.dev.EchoTimeout = b.dev.EchoTimeout = 50ms;
  for (int i = 0; i < 3; ++i) ASSERT_EQ(a.dev.attach(), b.dev.attach());
  std::uint32_t x = 0x9E3779B9U;
  auto next = [&x] {
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    return x;
  };
  constexpr std::array<std::uint8_t, 4> kCodes{0x09, 0x0E, 0x04, 0x20};
  std::array<std::uint8_t, 4> code{0x09, 0x09, 0x20, 0x09};  // per slot
  std::array<bool, 4> wants{false, true, true, false}, urgent{};
  std::uint64_t steady = 0;
  for (int i = 0; i < 200000; ++i) {
    const std::uint32_t v = next();
    if (v % 50 == 0) wants[1 + (v >> 8) % 3] = !wants[1 + (v >> 8) % 3];
    if (v % 70 == 1) code[1 + (v >> 8) % 3] = kCodes[(v >> 12) % 4];
    if (v % 90 == 2) urgent[1 + (v >> 8) % 3] = !urgent[1 + (v >> 8) % 3];
    // The echo: mostly the code asked for, sometimes late, wrong or none.
    const std::uint32_t e = (v >> 16) % 100;
    std::uint8_t echo = a.out[wg::w::kReadValueSelect];
    if (e < 3) echo = kCodes[(v >> 24) % 4];
    if (e >= 3 && e < 8) echo = a.in[wg::r::kReadValueSelected];  // not yet
    for (Scripted* s : {&a, &b}) {
      s->in[wg::r::kReadValueSelected] = echo;
      if (e == 8) s->in[wg::r::kStatus] ^= static_cast<std::uint8_t>(1U << ((v >> 24) % 8));
      if (e == 9) s->link.set_state(plc::io::DeviceState::Offline);
      if (e == 10) s->ctx.now += 60ms;  // past the echo timeout
      for (int slot = 1; slot < 4; ++slot)
        if (wants[static_cast<std::size_t>(slot)])
          s->dev.request_read(slot, code[static_cast<std::size_t>(slot)],
                              urgent[static_cast<std::size_t>(slot)]);
    }
    const bool was_held = a.dev.ReadHolder >= 0;
    a.scan([] {});
    b.ctx.now += 1ms;
    b.dev.scan_general(b.ctx);
    a.link.set_state(plc::io::DeviceState::Online);
    b.link.set_state(plc::io::DeviceState::Online);
    ASSERT_EQ(a.out, b.out) << "scan " << i;
    ASSERT_EQ(device_state(a.dev), device_state(b.dev)) << "scan " << i;
    for (int slot = 0; slot < 4; ++slot)
      for (std::uint8_t c : kCodes)
        ASSERT_EQ(a.dev.read_valid(slot, c), b.dev.read_valid(slot, c)) << "scan " << i;
    steady += was_held && a.dev.ReadHolder >= 0;
  }
  EXPECT_GT(steady, 50000u);  // the steady path did run
}

// §3.6 step 1: Write_Active (R[5].7) never drops: 16#8011.
TEST(Pr5510Faults, Spec36_WriteActiveStuckHigh) {
  Scripted s;
  s.in[wg::r::kStatus] = 1U << wg::r5::kWriteActive;
  wg::PR5510_WriteValue wv;
  wv.Code = 0x20;
  EXPECT_EQ(eid::kWriteBusyTimeout, run_to_error(s, wv, 3s));
  EXPECT_EQ(0, s.out[wg::w::kWriteValueSelect]);  // never sent
}

// §3.6 step 6: the device acknowledges but never clears Write_Active: 16#8013.
TEST(Pr5510Faults, Spec36_WriteActiveNeverReleased) {
  Scripted s;
  wg::PR5510_WriteValue wv;
  wv.Code = 0x20;
  wv.Device = &s.dev;
  wv.Execute = true;
  for (int i = 0; i < 3000 && !wv.Error; ++i) {
    s.scan([&] { wv(s.ctx); });
    if (s.out[wg::w::kWriteValueSelect] == 0x20) s.in[wg::r::kStatus] = 1U << wg::r5::kWriteActive;
  }
  EXPECT_TRUE(wv.Error);
  EXPECT_EQ(eid::kWriteReleaseTimeout, wv.ErrorID);
  EXPECT_EQ(0, s.out[wg::w::kWriteValueSelect]);  // step 5 was done
}

// Cmd_Busy (R[6].7) never drops after a command edge: 16#8014.
TEST(Pr5510Faults, Spec34_CmdBusyStuck) {
  Scripted s;
  s.in[wg::r::kCommand] = 1U << wg::r6::kCmdBusy;
  wg::PR5510_Command cmd;
  cmd.Command = wg::CommandBit::SetTare;
  EXPECT_EQ(eid::kCommandBusyTimeout, run_to_error(s, cmd, 3s));
  EXPECT_EQ(0, s.out[wg::w::kCommands]);  // the edge was released
}

// Cmd_Error with the error number readable from code 4 (§5.3): 16#812F;
// and with code 4 never answering: 16#81FF.
TEST(Pr5510Faults, Spec53_CmdErrorNumberOrUnknown) {
  {
    Scripted s;
    wg::PR5510_Command cmd;
    cmd.Command = wg::CommandBit::SetZero;
    cmd.Device = &s.dev;
    cmd.Execute = true;
    for (int i = 0; i < 3000 && !cmd.Error && !cmd.Done; ++i) {
      s.scan([&] { cmd(s.ctx); });
      if (s.out[wg::w::kCommands]) s.in[wg::r::kCommand] = 1U << wg::r6::kCmdError;
      // code 4: decimals 2, kg, d 1, last error 47
      wg::encode_raw(s.in, wg::pack_format({2, 3, 1, 47}), wg::Bus::Profibus);
    }
    EXPECT_EQ(eid::kDeviceErrorBase + 47, cmd.ErrorID);
  }
  {
    Scripted s;
    wg::PR5510_Command cmd;
    cmd.Command = wg::CommandBit::SetZero;
    cmd.Device = &s.dev;
    cmd.Execute = true;
    for (int i = 0; i < 5000 && !cmd.Error && !cmd.Done; ++i) {
      s.scan([&] { cmd(s.ctx); });
      if (s.out[wg::w::kCommands]) {
        s.in[wg::r::kCommand] = 1U << wg::r6::kCmdError;
        s.echo = false;  // from now on the read window never echoes
        s.in[wg::r::kReadValueSelected] = 0;
      }
    }
    EXPECT_EQ(eid::kDeviceErrorUnknown, cmd.ErrorID);
  }
}

// The device block's own start-up reads retry after an echo timeout: a
// device that answers late still becomes Ready.
TEST(Pr5510Faults, Spec72_StartUpReadsRetryAfterTimeout) {
  Scripted s;
  s.echo = false;
  for (int i = 0; i < 1500; ++i) s.scan([] {});
  EXPECT_FALSE(s.dev.Ready);
  s.echo = true;
  wg::encode_raw(s.in, 5000, wg::Bus::Profibus);
  for (int i = 0; i < 100; ++i) s.scan([] {});
  EXPECT_TRUE(s.dev.Ready);
}

// R[5..7] are decoded once per change of the three bytes (the device
// block's cache): after every scan status() is decode_status() of this
// scan's bytes, over runs where one byte changes, bytes repeat, the device
// goes off line and back, and all 24 bits move one at a time.
TEST(Pr5510Faults, Spec34_StatusDecodedEveryScanOfItsBytes) {
  Scripted s;
  std::uint32_t x = 0x2545F491U;  // xorshift: the same bytes every run
  auto next = [&x] {
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    return x;
  };
  const std::array<std::uint8_t, 3> at{wg::r::kStatus, wg::r::kCommand, wg::r::kWeighing};
  for (int i = 0; i < 20000; ++i) {
    const std::uint32_t v = next();
    switch (v % 5) {
      case 0:  // one bit of one byte flips
        s.in[at[(v >> 8) % 3]] ^= static_cast<std::uint8_t>(1U << ((v >> 12) % 8));
        break;
      case 1:  // all three new
        for (std::size_t k = 0; k < 3; ++k) s.in[at[k]] = static_cast<std::uint8_t>(v >> (8 * k));
        break;
      case 2:  // off line for a scan
        s.link.set_state(plc::io::DeviceState::Offline);
        break;
      default:  // the same bytes again
        break;
    }
    s.scan([] {});
    s.link.set_state(plc::io::DeviceState::Online);
    ASSERT_EQ(wg::decode_status(s.in), s.dev.status()) << "scan " << i;
  }
  for (std::size_t k = 0; k < 3; ++k)
    for (unsigned b = 0; b < 8; ++b) {
      s.in[at[k]] = static_cast<std::uint8_t>(1U << b);
      s.scan([] {});
      ASSERT_EQ(wg::decode_status(s.in), s.dev.status()) << "byte " << k << " bit " << b;
      s.in[at[k]] = 0;
    }
}
