// PnDevice hosting the real device models unchanged (DESIGN.md "one model,
// many transports"): the HIWIN E1 parameter channel (hiwin-e1-profinet.md
// §6.4, record write then read on 0xB02E) and the NORD F-parameter record
// (nord-profisafe.md §2.2) over PROFINET Write/Read, with the model's own
// refusal codes travelling back.
#include "plc/fb/drive/parameter_channel.hpp"
#include "plc/fb/safety/f_parameters.hpp"
#include "plc/profinet/description/builtin_descriptions.hpp"
#include "plc/profinet/device/record_status.hpp"
#include "test_device_harness.hpp"

namespace pn_test {
namespace {

std::unique_ptr<io::DeviceModel> make_model(const std::string& name, const io::ModelParams& p) {
  const io::DeviceModelFactory* f = io::DeviceModelRegistry::instance().find(name);
  EXPECT_NE(f, nullptr) << name;
  return f ? (*f)(p) : nullptr;
}

class DeviceModels : public DeviceHarness {
 protected:
  void host(const std::string& model, const io::ModelParams& p) {
    auto desc = pn::builtin_description(model, p);
    desc.station_name = model == "hiwin_e1" ? "conveyor" : "safety";
    desc.ip = dev_ip;
    make_device(desc, make_model(model, p));
  }
  std::optional<Answer> write(std::uint16_t index, std::span<const std::uint8_t> data) {
    const auto* io = desc_.io_submodule();
    const auto* mod = desc_.module_of(io);
    const pn::RecordWrite w{io->api, mod->slot, io->subslot, index, {data.begin(), data.end()}};
    // One MultipleWrite, as the controller sends start-up records.
    return call(pn::rpc::kOpWrite, pn::encode_write_request(1, kArUuid, std::span(&w, 1), true));
  }
  std::optional<Answer> read(std::uint16_t index) {
    const auto* io = desc_.io_submodule();
    pn::RecordRequestHeader h;
    h.ar_uuid = kArUuid;
    h.api = io->api;
    h.slot = desc_.module_of(io)->slot;
    h.subslot = io->subslot;
    h.index = index;
    h.record_data_length = io::kRecordMaxBytes;
    return call(pn::rpc::kOpRead, pn::encode_read_request(h));
  }
};

// §6.4 Table 4.3.1.1/4.3.1.2: read PNU 922 (telegram selection) -> 111.
TEST_F(DeviceModels, HiwinE1ParameterChannelOverWriteThenRead) {
  io::ModelParams p;
  p.set("telegram", "111");
  host("hiwin_e1", p);
  ASSERT_TRUE(connect(connect_request()).ok());  // records before PrmEnd, as at start-up
  plc::drive::ParamRequest req;
  req.reference = 0x21;
  req.request_id = 0x01;
  req.pnu = 922;
  std::array<std::uint8_t, 240> buf{};
  const std::size_t n = req.encode(buf);
  ASSERT_GT(n, 0u);
  const auto w = write(plc::drive::kParamRecordIndexLocal, std::span(buf.data(), n));
  ASSERT_TRUE(w.has_value());
  ASSERT_TRUE(w->ndr.status.ok()) << std::hex << w->ndr.status.value();
  run(milliseconds(5));
  const auto r = read(plc::drive::kParamRecordIndexLocal);
  ASSERT_TRUE(r.has_value());
  ASSERT_TRUE(r->ndr.status.ok()) << std::hex << r->ndr.status.value();
  pn::RecordResponseHeader h;
  std::span<const std::uint8_t> data;
  ASSERT_TRUE(pn::decode_read_response(r->args, h, data));
  plc::drive::ParamResponse res;
  ASSERT_TRUE(plc::drive::decode_response(data, res))
      << "record length " << data.size() << " header length " << h.record_data_length;
  EXPECT_EQ(res.reference, 0x21);
  EXPECT_EQ(res.response_id, 0x01);
  EXPECT_EQ(res.values[0], 111u);
}

// §2.2: a valid F-parameter block is taken; one with the wrong F_Dest_Add is
// refused with 5711, which arrives as the same RecordError.
TEST_F(DeviceModels, NordFParametersOverMultipleWriteWithTheModelsCodes) {
  io::ModelParams p;
  p.set("dip_address", "1");
  p.set("p802_3", "1");
  host("nord_profisafe", p);
  ASSERT_TRUE(connect(connect_request()).ok());
  plc::safety::FParameters fp;
  fp.dest_add = 2;  // the device's F-address is 1
  std::array<std::uint8_t, plc::safety::kFParamBlockSize> block{};
  plc::safety::encode(fp, block);
  auto a = write(plc::safety::kFParamRecordIndex, block);
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(pn::record_error_from(a->ndr.status), static_cast<io::RecordError>(5711));
  fp.dest_add = 1;
  plc::safety::encode(fp, block);
  a = write(plc::safety::kFParamRecordIndex, block);
  ASSERT_TRUE(a.has_value());
  EXPECT_TRUE(a->ndr.status.ok()) << std::hex << a->ndr.status.value();
}

}  // namespace
}  // namespace pn_test
