// PROFIsafe V2 CRC2 on the wire, checked against real traffic
// (shared/reference/profisafe-wire-vectors.md: 8 device telegrams of the
// public capture seb711/profisafe sniff/only_status_msgs.pcap, F_Par_CRC
// 0x22FF, 8 bytes of F-input data). The capture fixes the order in which the
// PDU enters CRC2: status/control byte, F-data from its last byte to its
// first, consecutive number as 4 bytes least significant first; register
// seeded with CRC1; CRC2 big-endian after the status byte.
//
// Both directions are checked: the host side accepts the captured device
// telegrams (codec and the whole host protocol), the device side produces
// them byte for byte (the codec the simulated device uses), and our
// simulated NORD device answers requests built by an independent reference
// encoder with telegrams that encoder accepts. The host -> device control
// telegram is not in the capture; it is taken to use the same order, and the
// last tests pin that reading.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <vector>

#include "bitwise_crc.hpp"
#include "captured_telegrams.hpp"
#include "plc/fb/safety/control_status_byte.hpp"
#include "plc/fb/safety/f_host_protocol.hpp"
#include "plc/fb/safety/f_parameters.hpp"
#include "plc/fb/safety/safety_pdu.hpp"
#include "plc/io/model_params.hpp"
#include "plc/sim/nord_profisafe_model.hpp"

namespace {

using namespace std::chrono_literals;
using namespace plc::safety;

using plctest::profisafe::CaptureRow;
using plctest::profisafe::kCapture;
using plctest::profisafe::kCaptureCrc1;
std::array<std::uint8_t, 12> capture_pdu(const CaptureRow& r) {
  std::array<std::uint8_t, 12> p{};
  for (std::size_t i = 0; i < 8; ++i) p[i] = r.fdata[i];
  p[8] = r.status;
  for (std::size_t i = 0; i < 3; ++i) p[9 + i] = r.crc2[i];
  return p;
}

// Independent reference, written from the vectors file alone: the bitwise
// CRC (no table), generator 0x5D6DCB (24 bit) or 0xF4ACFB13 (32 bit),
// register = CRC1; fed CB/SB, F-data last byte first, CN low/mid/high/0.
std::uint32_t ref_crc2(std::uint16_t crc1, std::uint8_t cb_sb,
                       const std::vector<std::uint8_t>& fdata, std::uint32_t cn) {
  std::vector<std::uint8_t> msg{cb_sb};
  for (auto it = fdata.rbegin(); it != fdata.rend(); ++it) msg.push_back(*it);
  msg.insert(msg.end(), {static_cast<std::uint8_t>(cn), static_cast<std::uint8_t>(cn >> 8),
                         static_cast<std::uint8_t>(cn >> 16), 0x00});
  return fdata.size() > 12 ? safety_test::bitwise_crc(0xF4ACFB13u, 32, crc1, msg)
                           : safety_test::bitwise_crc(0x5D6DCBu, 24, crc1, msg);
}

// The reference itself reproduces the vectors file's worked example (row 0:
// CRC2 over 40 00 00 00 00 04 00 01 41 00 00 00 00 from 0x22FF = 0xBB5FB5)
// and every row, so it can stand in for the capture below.
TEST(SafetyWireVectors, ReferenceEncoderReproducesCapture_RealTraffic) {
  for (const auto& r : kCapture) {
    const std::uint32_t want = (r.crc2[0] << 16) | (r.crc2[1] << 8) | r.crc2[2];
    EXPECT_EQ(ref_crc2(kCaptureCrc1, r.status, {r.fdata.begin(), r.fdata.end()}, r.cons_nr), want)
        << "row " << r.cons_nr;
  }
}

// Host side, codec: every captured device telegram checks with its
// consecutive number and CRC1, and with no other number.
TEST(SafetyWireVectors, HostAcceptsCapturedDeviceTelegrams_Crc2Order_RealTraffic) {
  for (const auto& r : kCapture) {
    const auto pdu = capture_pdu(r);
    EXPECT_TRUE(check_pdu(pdu, 8, r.cons_nr, kCaptureCrc1)) << "row " << r.cons_nr;
    EXPECT_FALSE(check_pdu(pdu, 8, r.cons_nr + 1, kCaptureCrc1)) << "row " << r.cons_nr;
  }
}

// Device side, codec: from the F-data, status byte and number the PDU
// builder produces the captured telegram byte for byte.
TEST(SafetyWireVectors, DeviceProducesCapturedTelegrams_Crc2Order_RealTraffic) {
  for (const auto& r : kCapture) {
    std::array<std::uint8_t, 12> pdu{};
    write_pdu(pdu, r.fdata, r.status, r.cons_nr, kCaptureCrc1);
    EXPECT_EQ(pdu, capture_pdu(r)) << "row " << r.cons_nr;
  }
}

// Host side, protocol: our F-host, configured like the captured connection
// (CRC1 0x22FF, 8 bytes F-input data), takes the 8 telegrams as the answers
// to its own requests without a single CRC error. It also follows the
// capture's consecutive-number semantics: number 0 with R_cons_nr for the
// reset request (answered with status bit 6 = cons_nr_R), then +1 per
// telegram, Toggle_h alternating in step with the device's Toggle_d.
TEST(SafetyWireVectors, HostProtocolRunsOnCapturedSequence_RealTraffic) {
  FHostProtocol host;
  host.configure(kCaptureCrc1, 8, 8, 100ms);
  host.start({});
  std::array<std::uint8_t, 12> req{}, resp{};
  std::array<std::uint8_t, 8> out{}, in{};
  FHostCommand cmd;
  plc::TIME now{};
  auto cycle = [&] {
    now += 1ms;
    host.cycle(now, resp, req, out, in, cmd);
  };
  // The capture starts with a reset whose request carried Toggle_h = 0. Our
  // host's first request after start-up carries Toggle_h = 1; a device that
  // answers it with CE_CRC makes the host reset again, now with Toggle_h = 0.
  cycle();
  ASSERT_TRUE(req[8] & cb::kRConsNr);
  ASSERT_TRUE(req[8] & cb::kToggleH);
  const std::array<std::uint8_t, 8> zeros{};
  write_pdu(resp, zeros, sb::kToggleD | sb::kCeCrc | sb::kFvActivated, 0, kCaptureCrc1);
  cycle();
  ASSERT_EQ(host.state(), FHostState::PassiveComm);
  const std::uint64_t crc_errors_before = host.crc_errors();

  for (const auto& r : kCapture) {
    // The outstanding request is the one this row answers.
    ASSERT_EQ(host.cons_nr(), r.cons_nr);
    ASSERT_EQ((req[8] & cb::kToggleH) != 0, (r.status & sb::kToggleD) != 0) << r.cons_nr;
    ASSERT_EQ((req[8] & cb::kRConsNr) != 0, r.cons_nr == 0) << r.cons_nr;
    EXPECT_EQ((r.status & sb::kConsNrR) != 0, r.cons_nr == 0);
    resp = capture_pdu(r);
    // Acknowledge as soon as ACK_REQ is shown (after the reset exchange).
    cmd.ack_rei = host.ack_req();
    cycle();
    ASSERT_NE(host.state(), FHostState::PassiveComm) << "row " << r.cons_nr;
  }
  EXPECT_EQ(host.crc_errors(), crc_errors_before);
  EXPECT_EQ(host.state(), FHostState::Run);
  EXPECT_FALSE(host.qbad());
  EXPECT_EQ(host.accepted_cons_nr(), 7u);
  EXPECT_EQ(in, kCapture[7].fdata);  // F-data handed over in wire order
}

// Host -> device: the control telegram is taken to use the same order as the
// status telegram (the capture holds device telegrams only). Our host's
// requests check with the reference encoder: NORD size (4 bytes, 3-byte
// CRC2) and 13 bytes (4-byte CRC2, the generator 0xF4ACFB13 still rests on
// the standard alone).
TEST(SafetyWireVectors, HostControlTelegramSameOrderAsStatus_Reading) {
  for (std::size_t n : {std::size_t{4}, std::size_t{13}}) {
    FHostProtocol host;
    host.configure(0x32CB, n, 4, 100ms);
    host.start({});
    std::vector<std::uint8_t> req(pdu_size(n)), out(n), in(4);
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<std::uint8_t>(0xA0 + i);
    std::array<std::uint8_t, 8> resp{};
    FHostCommand cmd;
    plc::TIME now{};
    std::uint32_t dev_cn = 0;
    for (int k = 0; k < 6; ++k) {
      now += 1ms;
      host.cycle(now, resp, req, out, in, cmd);
      const std::uint8_t control = req[n];
      const std::vector<std::uint8_t> data(req.begin(), req.begin() + static_cast<long>(n));
      const std::size_t len = crc2_length(n);
      std::uint32_t got = 0;
      for (std::size_t i = 0; i < len; ++i) got = (got << 8) | req[n + 1 + i];
      ASSERT_EQ(got, ref_crc2(0x32CB, control, data, host.cons_nr())) << "n " << n << " k " << k;
      // A device that follows the same order answers.
      dev_cn = (control & cb::kRConsNr) ? 0 : next_cons_nr(dev_cn);
      std::uint8_t status = (control & cb::kToggleH) ? sb::kToggleD : 0;
      if (control & cb::kActivateFv) status |= sb::kFvActivated;
      if (control & cb::kRConsNr) status |= sb::kConsNrR;
      const std::array<std::uint8_t, 4> d{1, 2, 3, 4};
      write_pdu(resp, d, status, dev_cn, 0x32CB);
    }
    EXPECT_EQ(host.state(), FHostState::Run) << "n " << n;
    EXPECT_EQ(host.crc_errors(), 0u);
  }
}

// The simulated NORD device, driven by requests from the reference encoder
// alone (no shared codec): it accepts them (no CE_CRC) and its answers check
// with the reference encoder, for the reset exchange and the following ones.
TEST(SafetyWireVectors, NordModelSpeaksCaptureOrderBothWays_RealTraffic) {
  plc::io::ModelParams mp;
  mp.set("dip_address", "1");
  mp.set("p802_3", "1");
  plc::sim::NordProfisafeModel m(mp);
  FParameters p;
  p.source_add = 10;
  p.dest_add = 1;
  std::array<std::uint8_t, kFParamBlockSize> blk{};
  encode(p, blk);
  ASSERT_EQ(m.write_record(kFParamRecordIndex, blk), plc::io::RecordError::None);
  const std::uint16_t crc1 = p.par_crc;

  std::array<std::uint8_t, 8> req{}, resp{};
  plc::TIME now{};
  bool toggle = true;
  for (std::uint32_t cn = 0; cn < 6; ++cn) {
    std::uint8_t control = toggle ? cb::kToggleH : 0;
    if (cn == 0) control |= cb::kRConsNr | cb::kActivateFv;
    if (cn == 1) control |= cb::kOaReq;
    const std::vector<std::uint8_t> data = {static_cast<std::uint8_t>(cn >= 2 ? 0x01 : 0), 0, 0, 0};
    for (std::size_t i = 0; i < 4; ++i) req[i] = data[i];
    req[4] = control;
    const std::uint32_t c = ref_crc2(crc1, control, data, cn);
    req[5] = static_cast<std::uint8_t>(c >> 16);
    req[6] = static_cast<std::uint8_t>(c >> 8);
    req[7] = static_cast<std::uint8_t>(c);
    now += 1ms;
    m.step(now, 1ms, req, resp);
    const std::uint8_t status = resp[4];
    EXPECT_FALSE(status & sb::kCeCrc) << "device refused request " << cn;
    EXPECT_EQ((status & sb::kToggleD) != 0, toggle) << cn;
    EXPECT_EQ((status & sb::kConsNrR) != 0, cn == 0) << cn;
    const std::vector<std::uint8_t> rdata(resp.begin(), resp.begin() + 4);
    const std::uint32_t want = ref_crc2(crc1, status, rdata, cn);
    EXPECT_EQ((std::uint32_t{resp[5]} << 16) | (resp[6] << 8) | resp[7], want) << cn;
    toggle = !toggle;
  }
  EXPECT_TRUE(m.ossd(0));  // SO1 switched on by the reference-encoded request
  EXPECT_EQ(m.crc_errors(), 0u);
}

}  // namespace
