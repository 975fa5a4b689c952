// Fuzz target: the PROFINET DCP parser (iec-io/profinet/wire/dcp.hpp) on
// whatever arrives on EtherType 0x8892 with a DCP FrameID. The input is a
// whole Ethernet frame (first byte: 0 = as is, 1 = with a VLAN tag
// inserted). Property: a message that decodes re-encodes to bytes that
// decode to the same message (the codec is a fixed point after one round).
#include <cstdint>
#include <vector>

#include "fuzz_input.hpp"
#include "plc/profinet/wire/dcp.hpp"

namespace pn = plc::profinet;

namespace {

bool same(const pn::DcpMessage& a, const pn::DcpMessage& b) {
  if (a.frame_id != b.frame_id || a.service_id != b.service_id ||
      a.service_type != b.service_type || a.xid != b.xid || a.blocks.size() != b.blocks.size())
    return false;
  for (std::size_t i = 0; i < a.blocks.size(); ++i) {
    const auto &x = a.blocks[i], &y = b.blocks[i];
    if (x.option != y.option || x.suboption != y.suboption || x.data != y.data) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  plc::fuzz::FuzzInput in(data, size);
  const bool tag = in.flag();
  const auto rest = in.bytes(in.remaining());
  std::vector<std::uint8_t> frame(rest.begin(), rest.end());
  if (tag && frame.size() >= 12) {
    const std::uint8_t vlan[] = {0x81, 0x00, 0xC0, 0x00};
    frame.insert(frame.begin() + 12, vlan, vlan + 4);
  }
  pn::PnFrameView v;
  if (!pn::decode_pn_frame(frame, v)) return 0;
  pn::DcpMessage m;
  if (!pn::decode_dcp(v.frame_id, v.pdu, m)) return 0;
  pn::DcpIdentity id;
  (void)pn::identity_from(m, id);
  pn::DcpSetRequest set;
  (void)pn::set_request_from(m, set);
  std::vector<pn::DcpSetResult> results;
  (void)pn::set_results_from(m, results);
  (void)pn::identify_filter(m);
  // Blocks longer than a block length can say cannot be re-encoded.
  for (const auto& b : m.blocks)
    if (b.data.size() > 0xFFF0) return 0;
  const auto again = pn::encode_dcp(m);
  pn::DcpMessage m2;
  if (!pn::decode_dcp(m.frame_id, again, m2) || !same(m, m2)) __builtin_trap();
  return 0;
}
