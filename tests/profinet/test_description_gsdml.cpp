// GSDML parsing (gsdml.hpp) on small files written here: idents, IO data
// lengths from the DataItems, API and FixedInSubslots, start-up records
// from ParameterRecordDataItem defaults (Const, Ref), module choice by ID
// or name and the DAP's AllowedInSlots, and errors located as FILE:LINE.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "plc/profinet/description/gsdml.hpp"

namespace pn = plc::profinet;

namespace {

std::string write(const std::string& name, const std::string& text) {
  const std::string path =
      ::testing::TempDir() + "pn_gsdml_" + std::to_string(::getpid()) + "_" + name + ".xml";
  std::ofstream(path) << text;
  return path;
}

// A vendor-style file: namespace, two DAPs, a module with a parameter record.
const char* const kFile = R"(<?xml version="1.0" encoding="UTF-8"?>
<ISO15745Profile xmlns="http://www.profibus.com/GSDML/2003/11/DeviceProfile">
  <ProfileBody>
    <DeviceIdentity VendorID="0x002A" DeviceID="0x0105"/>
    <ApplicationProcess>
      <DeviceAccessPointList>
        <DeviceAccessPointItem ID="DAP1" ModuleIdentNumber="0x00000100" MinDeviceInterval="8">
          <ModuleInfo><Name TextId="T_DAP1"/></ModuleInfo>
          <UseableModules>
            <ModuleItemRef ModuleItemTarget="M_IO" AllowedInSlots="1..2 4"/>
          </UseableModules>
          <VirtualSubmoduleList>
            <VirtualSubmoduleItem ID="S_DAP1" SubmoduleIdentNumber="0x101" FixedInSubslots="1"><IOData/></VirtualSubmoduleItem>
          </VirtualSubmoduleList>
          <SystemDefinedSubmoduleList>
            <InterfaceSubmoduleItem ID="IF" SubslotNumber="32768" SubmoduleIdentNumber="0x8000"/>
            <PortSubmoduleItem ID="P1" SubslotNumber="32769" SubmoduleIdentNumber="0x8001"/>
            <PortSubmoduleItem ID="P2" SubslotNumber="32770" SubmoduleIdentNumber="0x8002"/>
          </SystemDefinedSubmoduleList>
        </DeviceAccessPointItem>
        <DeviceAccessPointItem ID="DAP2" ModuleIdentNumber="200">
          <ModuleInfo><Name TextId="T_DAP2"/></ModuleInfo>
          <VirtualSubmoduleList>
            <VirtualSubmoduleItem ID="S_DAP2" SubmoduleIdentNumber="201"/>
          </VirtualSubmoduleList>
          <SystemDefinedSubmoduleList>
            <InterfaceSubmoduleItem ID="IF2" SubslotNumber="32768" SubmoduleIdentNumber="0x8000"/>
            <PortSubmoduleItem ID="P21" SubslotNumber="32769" SubmoduleIdentNumber="0x8001"/>
          </SystemDefinedSubmoduleList>
        </DeviceAccessPointItem>
      </DeviceAccessPointList>
      <ModuleList>
        <ModuleItem ID="M_IO" ModuleIdentNumber="0x30">
          <ModuleInfo><Name TextId="T_IO"/></ModuleInfo>
          <VirtualSubmoduleList>
            <VirtualSubmoduleItem ID="S_IO" SubmoduleIdentNumber="0x31" API="14848" FixedInSubslots="2">
              <IOData>
                <Input><DataItem DataType="Unsigned16" TextId="x"/><DataItem DataType="OctetString" Length="5" TextId="x"/></Input>
                <Output><DataItem DataType="Float32" TextId="x"/></Output>
              </IOData>
              <RecordDataList>
                <ParameterRecordDataItem Index="0x1000" Length="6">
                  <Const ByteOffset="0" Data="0x11,0x22"/>
                  <Ref DataType="Unsigned16" ByteOffset="2" DefaultValue="0x1234" TextId="x"/>
                  <Ref DataType="BitArea" ByteOffset="4" BitOffset="2" BitLength="3" DefaultValue="5" TextId="x"/>
                  <Ref DataType="Bit" ByteOffset="5" BitOffset="7" DefaultValue="1" TextId="x"/>
                </ParameterRecordDataItem>
              </RecordDataList>
            </VirtualSubmoduleItem>
          </VirtualSubmoduleList>
        </ModuleItem>
        <ModuleItem ID="M_OTHER" ModuleIdentNumber="0x40">
          <VirtualSubmoduleList><VirtualSubmoduleItem ID="S_O" SubmoduleIdentNumber="0x41"/></VirtualSubmoduleList>
        </ModuleItem>
      </ModuleList>
      <ExternalTextList><PrimaryLanguage>
        <Text TextId="T_DAP1" Value="Head 1"/><Text TextId="T_DAP2" Value="Head 2"/>
        <Text TextId="T_IO" Value="IO 2W"/>
      </PrimaryLanguage></ExternalTextList>
    </ApplicationProcess>
  </ProfileBody>
</ISO15745Profile>
)";

std::string error_of(const std::string& path, const pn::GsdmlSelection& sel) {
  try {
    pn::load_gsdml(path, sel);
  } catch (const pn::GsdmlError& e) {
    return e.what();
  }
  return "(none)";
}

}  // namespace

TEST(DescriptionGsdml, IdentsLengthsApiSubslotsAndRecordDefaults) {
  const auto path = write("full", kFile);
  const auto d = pn::load_gsdml(path, {"Head 1", {{4, "IO 2W"}}});
  EXPECT_EQ(d.vendor_id, 0x2A);
  EXPECT_EQ(d.device_id, 0x105);
  EXPECT_EQ(d.min_device_interval, std::chrono::microseconds(250));  // 8 x 31.25 us
  ASSERT_EQ(d.modules.size(), 2u);
  EXPECT_EQ(d.modules[0].module_ident, 0x100u);
  ASSERT_EQ(d.modules[0].submodules.size(), 4u);  // DAP, interface, two ports
  EXPECT_EQ(d.modules[0].submodules[3].subslot, 0x8002);
  const auto& m = d.modules[1];
  EXPECT_EQ(m.slot, 4);
  EXPECT_EQ(m.module_ident, 0x30u);
  ASSERT_EQ(m.submodules.size(), 1u);
  const auto& s = m.submodules[0];
  EXPECT_EQ(s.subslot, 2);
  EXPECT_EQ(s.api, 0x3A00u);
  EXPECT_EQ(s.submodule_ident, 0x31u);
  EXPECT_EQ(s.input_length, 7);
  EXPECT_EQ(s.output_length, 4);
  ASSERT_EQ(s.records.size(), 1u);
  EXPECT_EQ(s.records[0].index, 0x1000);
  // 11 22 | 12 34 (big-endian) | 5 << 2 = 0x14 | bit 7 = 0x80
  EXPECT_EQ(s.records[0].data, (std::vector<std::uint8_t>{0x11, 0x22, 0x12, 0x34, 0x14, 0x80}));
  ::unlink(path.c_str());
}

TEST(DescriptionGsdml, FirstDapByDefaultOtherDapById) {
  const auto path = write("daps", kFile);
  EXPECT_EQ(pn::load_gsdml(path, {}).modules[0].module_ident, 0x100u);
  const auto d2 = pn::load_gsdml(path, {"DAP2", {}});
  EXPECT_EQ(d2.modules[0].module_ident, 200u);
  EXPECT_EQ(d2.modules[0].submodules[0].subslot, 1);                // no FixedInSubslots: 1
  EXPECT_EQ(d2.min_device_interval, std::chrono::milliseconds(1));  // not given: default
  ::unlink(path.c_str());
}

TEST(DescriptionGsdml, ErrorsAreLocatedFileAndLine) {
  const auto path = write("errs", kFile);
  auto has = [](const std::string& what, const std::string& part) {
    return what.find(part) != std::string::npos;
  };
  // The DAP allows M_IO in slots 1..2 and 4 (its ModuleItemRef is on line 10).
  std::string e = error_of(path, {"", {{3, "M_IO"}}});
  EXPECT_TRUE(has(e, path + ":10:")) << e;
  EXPECT_TRUE(has(e, "slots 1..2 4")) << e;
  e = error_of(path, {"", {{1, "M_OTHER"}}});
  EXPECT_TRUE(has(e, "does not allow module 'M_OTHER'")) << e;
  e = error_of(path, {"DAP9", {}});
  EXPECT_TRUE(has(e, "no DeviceAccessPointItem 'DAP9'")) << e;
  EXPECT_TRUE(has(e, "DAP1, DAP2")) << e;
  e = error_of(path, {"", {{1, "M_IO"}, {1, "M_IO"}}});
  EXPECT_TRUE(has(e, "chosen twice")) << e;
  ::unlink(path.c_str());

  std::string broken = kFile;
  broken.replace(broken.find("Unsigned16\" TextId"), 10, "Unsigned17");
  const auto p2 = write("type", broken);
  e = error_of(p2, {"", {{1, "M_IO"}}});
  EXPECT_TRUE(has(e, p2 + ":38:")) << e;
  EXPECT_TRUE(has(e, "Unsigned17")) << e;
  ::unlink(p2.c_str());

  const auto p3 = write("xml", std::string(kFile).substr(0, 600));
  e = error_of(p3, {});
  EXPECT_TRUE(has(e, p3 + ":")) << e;
  EXPECT_FALSE(has(e, p3 + ":0:")) << e;  // libxml2 gives the line
  ::unlink(p3.c_str());

  e = error_of("/nonexistent/device.xml", {});
  EXPECT_TRUE(has(e, "/nonexistent/device.xml:")) << e;
  const auto p4 = write("root", "<?xml version=\"1.0\"?>\n<Other/>\n");
  EXPECT_TRUE(has(error_of(p4, {}), "not a GSDML file")) << error_of(p4, {});
  ::unlink(p4.c_str());
}

TEST(DescriptionGsdml, ModuleSelectionText) {
  const auto s = pn::parse_gsdml_modules(" 1=ID_Mod_Tel111 ; 3 = IO 2W;");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].slot, 1);
  EXPECT_EQ(s[0].module, "ID_Mod_Tel111");
  EXPECT_EQ(s[1].slot, 3);
  EXPECT_EQ(s[1].module, "IO 2W");
  EXPECT_THROW(pn::parse_gsdml_modules("ID_Mod"), std::invalid_argument);
  EXPECT_THROW(pn::parse_gsdml_modules("0=ID_Mod"), std::invalid_argument);
  EXPECT_THROW(pn::parse_gsdml_modules("x=ID_Mod"), std::invalid_argument);
}
