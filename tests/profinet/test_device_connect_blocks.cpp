// How the device reads the Connect's blocks, with the PNIO status codes of
// p-net's pf_cmrpc_rm_connect_interpret_ind (connect_check.hpp,
// check_connect_blocks): ARBlockReq first (0x01 0x00), at most two
// IOCRBlockReqs (CMRPC 0x03), each block exactly as long as its fields
// (block 0x01) and of version 1.0 (0x02 / 0x03), no unknown block (CMRPC
// 0x01), nothing after the last block (CMRPC 0x00). Byte-level mutations
// of a valid request.
#include <algorithm>
#include <functional>

#include "plc/profinet/device/connect_check.hpp"
#include "test_device_harness.hpp"

namespace pn_test {
namespace {

using Args = std::vector<std::uint8_t>;

// The args as separate blocks, each with its header.
std::vector<Args> blocks_of(const pn::ConnectRequest& req) {
  std::vector<Args> out;
  auto add = [&](auto const& b) {
    Args a;
    pn::ByteBuilder w(a);
    pn::encode_block(w, b);
    out.push_back(std::move(a));
  };
  add(req.ar);
  for (const auto& c : req.iocrs) add(c);
  add(req.alarm_cr);
  for (const auto& e : req.expected) add(e);
  return out;
}
Args join(const std::vector<Args>& blocks) {
  Args out;
  for (const auto& b : blocks) out.insert(out.end(), b.begin(), b.end());
  return out;
}
// Appends `n` zero octets to a block and counts them in its BlockLength.
void lengthen(Args& block, std::size_t n) {
  block.insert(block.end(), n, 0);
  const std::size_t len = (block[2] << 8 | block[3]) + n;
  block[2] = static_cast<std::uint8_t>(len >> 8);
  block[3] = static_cast<std::uint8_t>(len);
}

struct BlockRefusal {
  const char* name;
  std::function<void(std::vector<Args>&)>
      mutate;  // blocks: AR, IOCR in, IOCR out, AlarmCR, expected...
  std::uint8_t code1, code2;
};
void PrintTo(const BlockRefusal& r, std::ostream* os) { *os << r.name; }

const std::vector<BlockRefusal>& block_refusals() {
  static const std::vector<BlockRefusal> r = {
      {"ArBlockNotFirst", [](auto& b) { std::swap(b[0], b[1]); }, 0x01, 0x00},
      {"SecondArBlock", [](auto& b) { b.push_back(b[0]); }, 0x01, 0x00},
      // p-net takes no padding in ARBlockReq (BlockLength 54 + the name).
      {"ArBlockPaddedAfterAnOddStationName", [](auto& b) { lengthen(b[0], 1); }, 0x01, 0x01},
      {"ArBlockVersionHigh2", [](auto& b) { b[0][4] = 2; }, 0x01, 0x02},
      {"ArBlockVersionLow1", [](auto& b) { b[0][5] = 1; }, 0x01, 0x03},
      {"IocrBlockLongerThanItsFields", [](auto& b) { lengthen(b[1], 2); }, 0x02, 0x01},
      {"IocrBlockVersionLow1", [](auto& b) { b[2][5] = 1; }, 0x02, 0x03},
      {"ThirdIocrBlock", [](auto& b) { b.insert(b.begin() + 2, b[1]); }, 0x40, 0x03},
      {"AlarmCrBlockLongerThanItsFields", [](auto& b) { lengthen(b[3], 2); }, 0x04, 0x01},
      {"ExpectedBlockLongerThanItsFields", [](auto& b) { lengthen(b[4], 2); }, 0x03, 0x01},
      {"ExpectedBlockVersionHigh0", [](auto& b) { b[4][4] = 0; }, 0x03, 0x02},
      // ARVendorBlockReq (0x0108): a block this device does not read.
      {"UnknownBlock",
       [](auto& b) {
         b.push_back({0x01, 0x08, 0x00, 0x02, 0x01, 0x00});
       },
       0x40, 0x01},
      {"BlockRunsPastTheArgs",
       [](auto& b) {
         b.push_back({0x01, 0x03, 0x00, 0x40, 0x01, 0x00});
       },
       0x40, 0x01},
      {"BytesAfterTheLastBlock",
       [](auto& b) {
         b.push_back({0x00, 0x00, 0x00});
       },
       0x40, 0x00},
  };
  return r;
}

class DeviceConnectBlocks : public DeviceHarness,
                            public ::testing::WithParamInterface<BlockRefusal> {
 protected:
  void SetUp() override { make_device(); }
};

TEST_P(DeviceConnectBlocks, RefusedWithPnetsReadingCode) {
  auto req = connect_request();
  req.ar.station_name = "plc";  // odd: the padding row pads after it
  auto blocks = blocks_of(req);
  ASSERT_FALSE(pn::check_connect_blocks(join(blocks)).has_value());
  GetParam().mutate(blocks);
  const Args args = join(blocks);
  const auto want = pn::connect_refusal(GetParam().code1, GetParam().code2);
  EXPECT_EQ(pn::check_connect_blocks(args), want);
  const auto a = call(pn::rpc::kOpConnect, args);
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(a->ndr.status, want);
  EXPECT_EQ(dev->state(), pn::PnDeviceState::Idle);
}

INSTANTIATE_TEST_SUITE_P(PnetCmrpcReading, DeviceConnectBlocks,
                         ::testing::ValuesIn(block_refusals()),
                         [](const auto& info) { return std::string(info.param.name); });

class DeviceConnectBlockOrder : public DeviceHarness {
 protected:
  void SetUp() override { make_device(); }
};

// The blocks in another order than IEC 61158-6-10's (the expected
// submodules before the AlarmCR block, as Siemens controllers send them),
// and an ARRPCBlockReq (0x0107), are read: p-net takes them.
TEST_F(DeviceConnectBlockOrder, OtherBlockOrderAndArRpcBlockAreRead) {
  auto req = connect_request();
  auto blocks = blocks_of(req);
  std::rotate(blocks.begin() + 3, blocks.begin() + 4, blocks.end());  // AlarmCR last
  pn::ArRpcBlockReq rpc{0x8894};
  Args rpc_block;
  pn::ByteBuilder w(rpc_block);
  pn::encode_block(w, rpc);
  blocks.push_back(rpc_block);
  const Args args = join(blocks);
  EXPECT_FALSE(pn::check_connect_blocks(args).has_value());
  const auto a = call(pn::rpc::kOpConnect, args);
  ASSERT_TRUE(a.has_value());
  EXPECT_TRUE(a->ndr.status.ok()) << std::hex << a->ndr.status.value();
}

}  // namespace
}  // namespace pn_test
