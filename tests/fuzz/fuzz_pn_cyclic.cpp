// Fuzz target: the PROFINET real-time frame parsers (iec-io/profinet/wire/
// cyclic.hpp, alarm.hpp) and the IO data layout. The first byte picks:
//  0 a received RT_CLASS_1 frame (next byte: the expected C_SDU length,
//    0 = any): decode; what decodes re-encodes to the same frame
//    (property), and the accessors stay inside it;
//  1 an RTA alarm frame: decode; notifications and acks re-encode and
//    decode to the same alarm (property);
//  2 expected submodules from the input: compute_layout; the layout the
//    controller writes into its IOCRBlockReqs is the one a device reads
//    back from them (property), every offset inside the C_SDU.
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "fuzz_input.hpp"
#include "plc/profinet/wire/alarm.hpp"
#include "plc/profinet/wire/cyclic.hpp"

namespace pn = plc::profinet;
using plc::fuzz::FuzzInput;

namespace {

void check(bool ok) {
  if (!ok) __builtin_trap();
}

void cyclic(FuzzInput& in) {
  const std::size_t len = in.byte();
  const auto frame = in.bytes(in.remaining());
  pn::CyclicView v;
  if (!pn::decode_cyclic(frame, len, v)) return;
  check(v.c_sdu.data() >= frame.data() &&
        v.c_sdu.data() + v.c_sdu.size() <= frame.data() + frame.size());
  if (v.c_sdu.size() < pn::iocr::kMinCSduLength || v.c_sdu.size() > pn::iocr::kMaxCSduLength)
    return;
  std::array<std::uint8_t, pn::kMaxFrameLength> out{};
  const std::size_t n = pn::encode_cyclic(out, v.header, v.c_sdu);
  check(n > 0 && n <= frame.size());
  check(std::equal(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n), frame.begin()));
  const pn::IoDataObject o{0, 1, 1, static_cast<std::uint16_t>(len), 30};
  (void)pn::io_data(v.c_sdu, o);
  (void)pn::iops(v.c_sdu, o);
}

void alarm_frame(FuzzInput& in) {  // not alarm(): POSIX alarm() is in scope
  const auto frame = in.bytes(in.remaining());
  pn::PnFrameView v;
  if (!pn::decode_pn_frame(frame, v)) return;
  pn::RtaPdu p;
  if (!pn::decode_rta(v.frame_id, v.pdu, p)) return;
  if (p.notification) {
    const auto f =
        pn::encode_alarm_notification(v.dst, v.src, p.header, *p.notification, v.vlan_tci);
    pn::PnFrameView v2;
    pn::RtaPdu p2;
    check(pn::decode_pn_frame(f, v2).ok() && pn::decode_rta(v2.frame_id, v2.pdu, p2).ok());
    check(p2.notification && p2.notification->data == p.notification->data &&
          p2.notification->alarm_specifier == p.notification->alarm_specifier &&
          p2.header.send_seq == p.header.send_seq);
  }
  if (p.ack) {
    const auto f = pn::encode_alarm_ack(v.dst, v.src, p.header, *p.ack, v.vlan_tci);
    pn::PnFrameView v2;
    pn::RtaPdu p2;
    check(pn::decode_pn_frame(f, v2).ok() && pn::decode_rta(v2.frame_id, v2.pdu, p2).ok());
    check(p2.ack && p2.ack->status == p.ack->status);
  }
}

void layout(FuzzInput& in) {
  std::vector<pn::ExpectedSubmoduleBlockReq> exp(1);
  const std::size_t modules = in.byte() % 8;
  for (std::size_t m = 0; m < modules; ++m) {
    pn::ExpectedModule mod{
        in.byte() % 2 ? 0u : 0x3A00u, static_cast<std::uint16_t>(m), in.byte(), 0, {}};
    const std::size_t subs = 1 + in.byte() % 4;
    for (std::size_t s = 0; s < subs; ++s) {
      pn::ExpectedSubmodule sm;
      sm.subslot = static_cast<std::uint16_t>(s + 1);
      sm.submodule_ident = in.byte();
      sm.input_length = static_cast<std::uint16_t>(in.integral<std::uint16_t>() % 300);
      sm.output_length = static_cast<std::uint16_t>(in.integral<std::uint16_t>() % 300);
      mod.submodules.push_back(sm);
    }
    exp[0].modules.push_back(mod);
  }
  pn::CyclicLayout l;
  if (!pn::compute_layout(exp, l)) return;
  for (const auto* cr : {&l.input, &l.output}) {
    check(cr->c_sdu_length >= 40 && cr->c_sdu_length <= 1440);
    for (const auto& o : cr->data) check(o.iops_offset() < cr->c_sdu_length);
    for (const auto& o : cr->iocs) check(o.offset < cr->c_sdu_length);
  }
  pn::IocrBlockReq in_cr, out_cr;
  in_cr.iocr_type = pn::iocr::kTypeInput;
  out_cr.iocr_type = pn::iocr::kTypeOutput;
  pn::apply_layout(l.input, in_cr);
  pn::apply_layout(l.output, out_cr);
  pn::IocrLayout back;
  check(pn::layout_from_iocr(in_cr, exp, back).ok());
  check(back.data.size() == l.input.data.size() && back.iocs.size() == l.input.iocs.size());
  check(pn::layout_from_iocr(out_cr, exp, back).ok());
  check(back.data.size() == l.output.data.size() && back.iocs.size() == l.output.iocs.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  plc::fuzz::run_one_of(in, cyclic, alarm_frame, layout);
  return 0;
}
