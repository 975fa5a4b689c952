// Fuzz target: the PROFINET DCE/RPC side (iec-io/profinet/wire/rpc.hpp,
// blocks.hpp) on any UDP datagram to port 34964. The first byte picks:
//  0 a whole datagram: CL header, NDR request or response (by packet type),
//    then the blocks of its opnum (Connect, Release/Control, Read, Write);
//  1 NDR args of a Connect request;  2 of a Connect response;
//  3 of a Write request;  4 of a Write response;  5 of a Read response;
//  6 a control block.
// Property: what decodes re-encodes to bytes that decode again and
// re-encode to the same bytes (one round reaches a fixed point).
#include <cstdint>
#include <vector>

#include "fuzz_input.hpp"
#include "plc/profinet/wire/blocks.hpp"
#include "plc/profinet/wire/rpc.hpp"

namespace pn = plc::profinet;
using Bytes = std::vector<std::uint8_t>;

namespace {

void check(bool ok) {
  if (!ok) __builtin_trap();
}

void connect_request(std::span<const std::uint8_t> args) {
  pn::ConnectRequest c;
  if (!pn::decode_connect_request(args, c)) return;
  const Bytes e1 = pn::encode_connect_request(c);
  pn::ConnectRequest c2;
  check(pn::decode_connect_request(e1, c2).ok());
  check(pn::encode_connect_request(c2) == e1);
}

void connect_response(std::span<const std::uint8_t> args) {
  pn::ConnectResponse c;
  if (!pn::decode_connect_response(args, c)) return;
  const Bytes e1 = pn::encode_connect_response(c);
  pn::ConnectResponse c2;
  check(pn::decode_connect_response(e1, c2).ok());
  check(pn::encode_connect_response(c2) == e1);
}

void write_request(std::span<const std::uint8_t> args) {
  pn::WriteRequest w;
  if (!pn::decode_write_request(args, w)) return;
  std::vector<pn::RecordWrite> records;
  if (w.multiple()) {
    for (std::size_t i = 0; i < w.sub_headers.size(); ++i) {
      const auto& h = w.sub_headers[i];
      records.push_back(
          {h.api, h.slot, h.subslot, h.index, {w.sub_data[i].begin(), w.sub_data[i].end()}});
    }
    if (records.empty()) return;
  } else {
    records.push_back({w.header.api,
                       w.header.slot,
                       w.header.subslot,
                       w.header.index,
                       {w.data.begin(), w.data.end()}});
  }
  const Bytes e1 =
      pn::encode_write_request(w.header.seq_number, w.header.ar_uuid, records, w.multiple());
  pn::WriteRequest w2;
  check(pn::decode_write_request(e1, w2).ok());
  check(w2.sub_headers.size() == w.sub_headers.size());
}

void write_response(std::span<const std::uint8_t> args) {
  pn::WriteResponse w;
  if (!pn::decode_write_response(args, w)) return;
  const Bytes e1 = pn::encode_write_response(w);
  pn::WriteResponse w2;
  check(pn::decode_write_response(e1, w2).ok());
  check(pn::encode_write_response(w2) == e1);
}

void read_response(std::span<const std::uint8_t> args) {
  pn::RecordResponseHeader h;
  std::span<const std::uint8_t> data;
  if (!pn::decode_read_response(args, h, data)) return;
  const Bytes e1 = pn::encode_read_response(h, data);
  check(e1.size() == args.size());
  pn::RecordRequestHeader rq;
  (void)pn::decode_read_request(args, rq);
}

void control(std::span<const std::uint8_t> args) {
  pn::ControlBlock c;
  if (!pn::decode_control(args, c)) return;
  pn::ControlBlock c2;
  check(pn::decode_control(pn::encode_control(c), c2).ok());
  check(c2.ar_uuid == c.ar_uuid && c2.command == c.command);
}

void datagram(std::span<const std::uint8_t> d) {
  pn::RpcPdu p;
  if (!pn::decode_rpc(d, p)) return;
  std::span<const std::uint8_t> args;
  const bool le = p.header.little_endian;
  if (p.header.packet_type == pn::rpc::kRequest) {
    pn::NdrRequest n;
    if (!pn::decode_ndr_request(p.body, le, n)) return;
    args = n.args;
    check(pn::encode_ndr_request(n.args_maximum, n.args, le).size() == 20 + args.size());
  } else if (p.header.packet_type == pn::rpc::kResponse) {
    pn::NdrResponse n;
    if (!pn::decode_ndr_response(p.body, le, n)) return;
    args = n.args;
  } else {
    return;
  }
  const bool request = p.header.packet_type == pn::rpc::kRequest;
  switch (p.header.opnum) {
    case pn::rpc::kOpConnect:
      request ? connect_request(args) : connect_response(args);
      break;
    case pn::rpc::kOpWrite:
      request ? write_request(args) : write_response(args);
      break;
    case pn::rpc::kOpRead:
      read_response(args);
      break;
    default:
      control(args);
      break;
  }
  // The header re-encodes to the same 80 bytes (drep kept).
  const Bytes h = pn::encode_rpc(p.header, p.body);
  pn::RpcPdu p2;
  check(pn::decode_rpc(h, p2).ok());
  check(p2.header.object == p.header.object && p2.header.opnum == p.header.opnum &&
        p2.body.size() == p.body.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  plc::fuzz::FuzzInput in(data, size);
  const std::uint8_t pick = in.byte();
  const auto rest = in.bytes(in.remaining());
  switch (pick % 7) {
    case 0:
      datagram(rest);
      break;
    case 1:
      connect_request(rest);
      break;
    case 2:
      connect_response(rest);
      break;
    case 3:
      write_request(rest);
      break;
    case 4:
      write_response(rest);
      break;
    case 5:
      read_response(rest);
      break;
    default:
      control(rest);
      break;
  }
  return 0;
}
