// DeviceNet explicit services on the record path (explicit_message.hpp): the
// request bytes reach a model through DeviceModel::query_record, error
// responses carry the §11.1 general status (toyo-vf66-devicenet.md Table 5.2).
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "plc/io/device_model.hpp"
#include "plc/io/explicit_message.hpp"
#include "plc/io/sim_device.hpp"

namespace io = plc::io;
namespace em = plc::io::explicit_msg;

namespace {

// Answers Get_Attribute_Single on 0x2A/1/7 (Speed Actual, INT) with 1800 rpm,
// and refuses everything else with 0x14 Attribute not supported.
class SpeedObject final : public io::DeviceModel {
 public:
  std::size_t input_size() const override { return 4; }
  std::size_t output_size() const override { return 4; }
  void step(plc::TIME, plc::TIME, std::span<const std::uint8_t>, std::span<std::uint8_t>) override {
  }
  io::RecordError query_record(std::uint16_t index, std::span<const std::uint8_t> request,
                               std::span<std::uint8_t> out, std::size_t& length) override {
    seen.assign(request.begin(), request.end());
    const auto r = em::decode_request(index, request);
    length = 0;
    if (r && r->service == em::kGetAttributeSingle && r->path.cls == 0x2A &&
        r->path.instance == 1 && r->path.attribute == 7) {
      out[0] = 0x08;  // 1800 = 0x0708, little-endian on the wire
      out[1] = 0x07;
      length = 2;
      return io::RecordError::None;
    }
    return static_cast<io::RecordError>(em::error_code(em::kAttributeNotSupported));
  }
  std::vector<std::uint8_t> seen;
};

// A model that knows only plain records.
class PlainRecords final : public io::DeviceModel {
 public:
  std::size_t input_size() const override { return 1; }
  std::size_t output_size() const override { return 1; }
  void step(plc::TIME, plc::TIME, std::span<const std::uint8_t>, std::span<std::uint8_t>) override {
  }
  io::RecordError read_record(std::uint16_t, std::span<std::uint8_t> out,
                              std::size_t& length) override {
    out[0] = 0x5A;
    length = 1;
    return io::RecordError::None;
  }
};

std::vector<std::uint8_t> request_bytes(std::uint8_t service, em::Path p,
                                        std::span<const std::uint8_t> data = {}) {
  std::array<std::uint8_t, 16> buf{};
  const std::size_t n = em::encode_request(service, p, data, buf);
  return {buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n)};
}

}  // namespace

TEST(ExplicitRecord, IndexCarriesTheServiceCodeOfSection1_5) {
  EXPECT_EQ(em::record_index(em::kGetAttributeSingle), 0xD00E);
  EXPECT_EQ(em::record_index(em::kSetAttributeSingle), 0xD010);
  EXPECT_EQ(em::record_index(em::kReset), 0xD005);
  EXPECT_TRUE(em::is_explicit_index(0xD00E));
  EXPECT_FALSE(em::is_explicit_index(0x002F)) << "a PROFIdrive parameter record stays a record";
  EXPECT_EQ(em::service_of(0xD010), em::kSetAttributeSingle);
}

TEST(ExplicitRecord, RequestBytesFollowThe8_8BodyFormatOfSection1_4) {
  // Set_Attribute_Single 0x29/1/5 NetCtrl := 1: class, instance, attribute, data.
  const std::array<std::uint8_t, 1> one{1};
  EXPECT_EQ(request_bytes(em::kSetAttributeSingle, {0x29, 1, 5}, one),
            (std::vector<std::uint8_t>{0x29, 0x01, 0x05, 0x01}));
  // Reset names no attribute.
  EXPECT_EQ(request_bytes(em::kReset, {0x01, 1, 0}), (std::vector<std::uint8_t>{0x01, 0x01}));
  const auto bytes = request_bytes(em::kSetAttributeSingle, {0x29, 1, 5}, one);
  const auto r = em::decode_request(em::record_index(em::kSetAttributeSingle), bytes);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->path.cls, 0x29);
  EXPECT_EQ(r->path.attribute, 5);
  ASSERT_EQ(r->data.size(), 1u);
  EXPECT_FALSE(em::decode_request(em::record_index(em::kGetAttributeSingle),
                                  std::array<std::uint8_t, 2>{0x2A, 1}))
      << "Get_Attribute_Single without an attribute id is too short";
  std::array<std::uint8_t, 3> small{};
  EXPECT_EQ(em::encode_request(em::kSetAttributeSingle, {0x29, 1, 5}, one, small), 0u)
      << "does not fit: nothing written";
}

TEST(ExplicitRecord, ErrorCodeCarriesGeneralStatusOfTable5_2) {
  const std::uint16_t c = em::error_code(em::kAttributeNotSettable);
  EXPECT_EQ(c, 0x0EFF);
  EXPECT_EQ(em::general_status(c), 0x0E);
  EXPECT_EQ(em::additional_code(c), 0xFF);
  EXPECT_GE(em::error_code(em::kResourceUnavailable, 0), 0x100) << "above the plugin-level codes";
}

TEST(ExplicitRecord, SimDeviceHandsTheRequestBytesToTheModel) {
  auto model = std::make_unique<SpeedObject>();
  SpeedObject* m = model.get();
  io::SimDevice dev(std::move(model));
  io::RecordRequest r;
  const auto req = request_bytes(em::kGetAttributeSingle, {0x2A, 1, 7});
  ASSERT_TRUE(r.prepare_read(em::record_index(em::kGetAttributeSingle), req));
  ASSERT_TRUE(dev.link().submit(r));
  dev.step(plc::TIME{}, std::chrono::milliseconds(1));
  EXPECT_EQ(m->seen, req);
  ASSERT_EQ(r.status(), io::RecordStatus::Done);
  EXPECT_EQ(r.data().size(), 2u);
  EXPECT_EQ(r.data()[0] | (r.data()[1] << 8), 1800);

  io::RecordRequest bad;
  ASSERT_TRUE(bad.prepare_read(em::record_index(em::kGetAttributeSingle),
                               request_bytes(em::kGetAttributeSingle, {0x2A, 1, 99})));
  ASSERT_TRUE(dev.link().submit(bad));
  dev.step(plc::TIME{}, std::chrono::milliseconds(1));
  ASSERT_EQ(bad.status(), io::RecordStatus::Error);
  EXPECT_EQ(em::general_status(bad.error_code()), em::kAttributeNotSupported);
}

TEST(ExplicitRecord, ModelWithoutQueryRecordRefusesRequestBytesButServesPlainReads) {
  io::SimDevice dev(std::make_unique<PlainRecords>());
  io::RecordRequest plain;
  plain.prepare_read(7);
  ASSERT_TRUE(dev.link().submit(plain));
  dev.step(plc::TIME{}, std::chrono::milliseconds(1));
  ASSERT_EQ(plain.status(), io::RecordStatus::Done);
  EXPECT_EQ(plain.data()[0], 0x5A);

  io::RecordRequest with_bytes;
  ASSERT_TRUE(with_bytes.prepare_read(7, std::array<std::uint8_t, 2>{1, 2}));
  ASSERT_TRUE(dev.link().submit(with_bytes));
  dev.step(plc::TIME{}, std::chrono::milliseconds(1));
  ASSERT_EQ(with_bytes.status(), io::RecordStatus::Error);
  EXPECT_EQ(with_bytes.error(), io::RecordError::InvalidIndex);
}
