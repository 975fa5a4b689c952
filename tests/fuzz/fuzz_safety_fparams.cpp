// Fuzz target: the 14-byte F-parameter block (fblocks/safety/
// f_parameters.hpp, spec nord-profisafe.md §2.2) and the simulated NORD
// F-device's checks of it (§8.3: codes 5711-5725 in a fixed order):
//  * decode -> encode is stable (a second round gives the same bytes);
//  * the device takes any record write (any index, any length, any block,
//    also blocks with a right CRC1 so the checks behind it are reached),
//    record reads and power cycles in any order, and answers each refused
//    block with a record error.
#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <string>

#include "fuzz_input.hpp"
#include "plc/fb/safety/f_parameters.hpp"
#include "plc/sim/nord_profisafe_model.hpp"

using namespace plc;
using namespace plc::safety;
using plc::fuzz::FuzzInput;
using namespace std::chrono_literals;

namespace {
constexpr int kMaxSteps = 500;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  io::ModelParams params;
  params.set("dip_address", std::to_string(in.byte()));
  params.set("p831", std::to_string(in.integral<std::uint16_t>()));
  params.set("max_sil", std::to_string(in.byte() % 4));
  params.set("p840", "305441741");
  sim::NordProfisafeModel model(params);

  std::array<std::uint8_t, io::kRecordMaxBytes> buf{};
  std::array<std::uint8_t, sim::NordProfisafeModel::kPdu> req{}, resp{};
  TIME now{};
  for (int i = 0; i < kMaxSteps && !in.empty(); ++i) {
    const std::uint8_t op = in.byte();
    switch (op & 7) {
      case 0: {  // decode -> encode -> decode -> encode
        std::array<std::uint8_t, kFParamBlockSize> raw{}, once{}, twice{};
        in.fill(raw);
        FParameters a = decode(raw);
        encode(a, once, false);
        FParameters b = decode(once);
        encode(b, twice, false);
        if (once != twice) __builtin_trap();
        break;
      }
      case 1: {  // a block with a right CRC1 from any fields
        std::array<std::uint8_t, kFParamBlockSize> raw{};
        in.fill(raw);
        FParameters p = decode(raw);
        encode(p, raw, true);
        (void)model.write_record(kFParamRecordIndex, raw);
        break;
      }
      case 2:  // any bytes, any length, any index
        (void)model.write_record((op & 8) ? in.integral<std::uint16_t>() : kFParamRecordIndex,
                                 in.bytes(in.byte()));
        break;
      case 3: {
        std::size_t len = 0;
        const auto room = std::span(buf).first(in.byte() % (buf.size() + 1));
        if (model.read_record((op & 8) ? in.integral<std::uint16_t>() : kNordDiagRecordIndex, room,
                              len) == io::RecordError::None &&
            len > room.size())
          __builtin_trap();
        break;
      }
      case 4:
        model.power_cycle();
        break;
      default:
        if (op & 8) in.fill(req);
        now += 1ms;
        model.step(now, 1ms, req, resp);
        break;
    }
  }
  return 0;
}
