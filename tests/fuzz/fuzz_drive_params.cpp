// Fuzz target: the PROFIdrive parameter channel (fblocks/drive/
// parameter_channel.hpp, spec hiwin-e1-profinet.md §6.4, Tables 4.3.1.1 -
// 4.3.6.1) on both ends of the wire. The first byte picks the part:
//  0 the decoders: a request or response that decodes re-encodes to bytes
//    that decode to the same fields;
//  1 the simulated E1's parameter server takes any record write; whatever
//    it answers on the following read decodes as a response;
//  2 SinaPara (ParamClient) takes any record answers and errors from the
//    drive, with any block inputs.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>

#include "fuzz_device.hpp"
#include "fuzz_input.hpp"
#include "hiwin_e1/hiwin_e1_model.hpp"
#include "plc/fb/drive/parameter_channel.hpp"
#include "plc/fb/drive/sina_para.hpp"
#include "plc/io/record_request.hpp"

using namespace plc;
using namespace plc::drive;
using plc::fuzz::FuzzInput;
using namespace std::chrono_literals;

namespace {

constexpr int kMaxSteps = 2000;

// The values a request or response carries (num_values may claim more
// when the format has no values to read).
template <class T>
bool same_values(const T& a, const T& b) {
  const std::size_t n = std::min<std::size_t>(a.num_values, kParamMaxValues);
  return std::equal(a.values.begin(), a.values.begin() + n, b.values.begin());
}

bool same(const ParamRequest& a, const ParamRequest& b) {
  return a.reference == b.reference && a.request_id == b.request_id && a.do_id == b.do_id &&
         a.num_parameters == b.num_parameters && a.attribute == b.attribute &&
         a.num_elements == b.num_elements && a.pnu == b.pnu && a.subindex == b.subindex &&
         a.format == b.format && a.num_values == b.num_values && same_values(a, b);
}
bool same(const ParamResponse& a, const ParamResponse& b) {
  return a.reference == b.reference && a.response_id == b.response_id && a.do_id == b.do_id &&
         a.num_parameters == b.num_parameters && a.format == b.format &&
         a.num_values == b.num_values && a.error_no == b.error_no && same_values(a, b);
}

void decoders(FuzzInput& in) {
  const auto wire = in.bytes(in.remaining());
  std::array<std::uint8_t, io::kRecordMaxBytes> buf{};
  ParamRequest rq, rq2;
  if (decode_request(wire, rq) == ParseResult::Ok) {
    const std::size_t n = rq.encode(buf);
    if (n > 0 &&
        (decode_request(std::span(buf).first(n), rq2) != ParseResult::Ok || !same(rq, rq2)))
      __builtin_trap();
  }
  ParamResponse rs, rs2;
  if (decode_response(wire, rs)) {
    const std::size_t n = rs.encode(buf);
    if (n > 0 && (!decode_response(std::span(buf).first(n), rs2) || !same(rs, rs2)))
      __builtin_trap();
  }
}

void parameter_server(FuzzInput& in) {
  sim::HiwinE1Model model(sim::HiwinE1Config{});
  static constexpr std::uint16_t kIndex[] = {kParamRecordIndex, kParamRecordIndexLocal,
                                             kParamRecordIndexGlobal, 0x0030};
  std::array<std::uint8_t, Telegram111Out::kBytes> out{};
  std::array<std::uint8_t, Telegram111In::kBytes> back{};
  std::array<std::uint8_t, io::kRecordMaxBytes> answer{};
  TIME now{};
  for (int i = 0; i < kMaxSteps && !in.empty(); ++i) {
    const std::uint8_t op = in.byte();
    const std::uint16_t index = kIndex[(op >> 2) & 3];
    if ((op & 3) == 0) {
      (void)model.write_record(index, in.bytes(in.byte()));
    } else if ((op & 3) == 1) {
      std::size_t len = 0;
      const auto room = std::span(answer).first(in.byte() % (answer.size() + 1));
      if (model.read_record(index, room, len) == io::RecordError::None) {
        ParamResponse r;
        if (len > room.size() || (index != 0x0030 && !decode_response(room.first(len), r)))
          __builtin_trap();  // the drive's own response must be well-formed
      }
    } else {
      if (op & 0x10) in.fill(out);
      now += 1ms;
      model.step(now, 1ms, out, back);
    }
  }
}

void sina_para(FuzzInput& in) {
  DriveAxis axis;
  axis.SignOfLifeCheck = false;
  const auto dev = fuzz::fuzz_device(in, Telegram111In::kBytes, Telegram111Out::kBytes);
  dev->bind(axis.Port);
  SinaPara para;
  ScanContext ctx{TIME{}, 1ms, 0};
  for (int i = 0; i < kMaxSteps && !in.empty(); ++i) {
    const std::uint8_t flags = in.byte();
    para.Start = flags & 1;
    if (flags & 2) {  // new request inputs
      para.ReadWrite = flags & 4;
      para.Pnu = in.integral<UINT>();
      para.Subindex = in.integral<UINT>();
      para.Count = in.byte();
      para.Format = in.byte();
      para.RecordIndex = (flags & 8) ? in.integral<UINT>() : kParamRecordIndex;
      para.Timeout = std::chrono::milliseconds(in.byte());
      for (std::size_t k = 0; k < 4; ++k) para.Values[k] = in.integral<LREAL>();
    }
    para(ctx, axis);
    ctx.now += 1ms;
    ++ctx.cycle;
    dev->step(ctx.now, 1ms);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  plc::fuzz::run_one_of(in, decoders, parameter_server, sina_para);
  return 0;
}
