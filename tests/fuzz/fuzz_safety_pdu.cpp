// Fuzz target: PROFIsafe PDUs (fblocks/safety/safety_pdu.hpp, spec
// nord-profisafe.md §2.1, §2.6, §8.2, §8.3) on both ends of the wire. The
// first byte picks the part:
//  0 CRC2: a PDU built by write_pdu checks, and any single flipped bit makes
//    check_pdu refuse it (a CRC with more than one term in its generator
//    finds every 1-bit error); check_pdu of any bytes never reads outside;
//  1 the F-host (F_MODULE) takes any PDU and record answers from the
//    device: while QBAD is set, every F-input the application sees is 0;
//  2 the simulated NORD F-device takes any request PDU after its
//    F-parameters, including requests with a right CRC2 for nearby
//    consecutive numbers, so its state machine gets past the CRC check.
#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <string>

#include "fuzz_device.hpp"
#include "fuzz_input.hpp"
#include "plc/fb/safety/f_module.hpp"
#include "plc/fb/safety/nord_fdata_bits.hpp"
#include "plc/fb/safety/safety_pdu.hpp"
#include "plc/sim/nord_profisafe_model.hpp"

using namespace plc;
using namespace plc::safety;
using plc::fuzz::FuzzInput;
using namespace std::chrono_literals;

namespace {

constexpr int kMaxScans = 2000;

void crc2(FuzzInput& in) {
  const std::size_t n = in.byte() % kMaxFData + 1;
  std::array<std::uint8_t, kMaxFData> fdata{};
  in.fill(std::span(fdata).first(n));
  const std::uint8_t cb = in.byte();
  const std::uint32_t cn = in.integral<std::uint32_t>() & 0xFFFFFF;
  const auto seed = in.integral<std::uint16_t>();
  std::array<std::uint8_t, pdu_size(kMaxFData)> pdu{};
  const auto p = std::span(pdu).first(pdu_size(n));
  write_pdu(p, std::span(fdata).first(n), cb, cn, seed);
  if (!check_pdu(p, n, cn, seed)) __builtin_trap();
  const std::size_t bit = in.integral<std::uint16_t>() % (p.size() * 8);
  p[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
  if (check_pdu(p, n, cn, seed)) __builtin_trap();
  // Any bytes, any claimed F-data length.
  (void)check_pdu(in.bytes(in.byte()), in.byte(), cn, seed);
}

void f_host(FuzzInput& in) {
  F_MODULE<nord::kFDataBytes, nord::kFDataBytes> fmod;
  const auto dev = fuzz::fuzz_device(in, fmod.kInPdu, fmod.kOutPdu);
  dev->bind(fmod.port);
  fmod.F_WD_Time = 1 + in.byte();
  ScanContext ctx{TIME{}, 1ms, 0};
  for (int i = 0; i < kMaxScans && !in.empty(); ++i) {
    const std::uint8_t flags = in.byte();
    fmod.PASS_ON = flags & 1;
    fmod.ACK_NEC = flags & 2;
    fmod.ACK_REI = flags & 4;
    fmod.IPAR_EN = flags & 8;
    if (flags & 16)
      for (BYTE& b : fmod.OUT_DATA) b = in.byte();
    fmod(ctx);
    if (fmod.QBAD)
      for (BYTE b : fmod.IN_DATA)
        if (b != 0) __builtin_trap();  // passivated: fail-safe values (0) only
    ctx.now += 1ms;
    ++ctx.cycle;
    dev->step(ctx.now, 1ms);
  }
}

void f_device(FuzzInput& in) {
  io::ModelParams params;
  for (const auto& [k, v] : std::map<std::string, std::string>{{"dip_address", "1"},
                                                               {"p840", "305441741"},
                                                               {"p802_1", "1"},
                                                               {"p802_2", "1"},
                                                               {"p802_3", "1"},
                                                               {"p810", "1"},
                                                               {"p820_1", "1"},
                                                               {"p820_2", "1"}})
    params.set(k, v);
  sim::NordProfisafeModel model(params);
  FParameters fp;
  fp.source_add = 10;
  fp.dest_add = 1;
  fp.wd_time_ms = 1 + in.byte();
  fp.ipar_crc = 0x1234ABCD;
  std::array<std::uint8_t, kFParamBlockSize> block{};
  encode(fp, block);
  if (in.flag()) in.fill(block);  // any block instead of the right one
  (void)model.write_record(kFParamRecordIndex, block);

  std::array<std::uint8_t, sim::NordProfisafeModel::kPdu> req{}, resp{};
  TIME now{};
  for (int i = 0; i < kMaxScans && !in.empty(); ++i) {
    const std::uint8_t how = in.byte();
    if ((how & 3) == 1) {  // any bytes
      in.fill(req);
    } else if ((how & 3) == 2) {  // a request with a right CRC2 for a nearby number
      std::array<std::uint8_t, nord::kFDataBytes> fdata{};
      in.fill(fdata);
      const std::uint8_t cb = in.byte();
      const std::uint32_t cn = next_cons_nr(model.cons_nr()) + (how >> 2) % 3 - 1;
      write_pdu(req, fdata, cb, cn, fp.par_crc);
    }  // else: the host repeats its last request
    now += 1ms;
    model.step(now, 1ms, req, resp);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  plc::fuzz::run_one_of(in, crc2, f_host, f_device);
  return 0;
}
