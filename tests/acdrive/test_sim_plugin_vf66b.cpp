// The VF66B model by name ("vf66b") in the in-process sim plugin, driven by
// AcDrive through the plugin's latch/publish/step cycle as the runtime
// drives it, in virtual time; params as a cell config gives them.
#include <gtest/gtest.h>

#include <vector>

#include "plc/fb/acdrive/ac_drive.hpp"
#include "plc/io/sim_plugin.hpp"

namespace plc::acdrive {

using namespace std::chrono_literals;

namespace {
io::DeviceSpec vf66b_spec(const std::vector<std::pair<std::string, std::string>>& kv) {
  io::DeviceSpec s;
  s.name = "conveyor";
  s.model = "vf66b";
  for (const auto& [k, v] : kv) s.params.set(k, v);
  return s;
}
}  // namespace

TEST(Vf66bSimPlugin, SizesFromJ09J10AndStrictParams_Section7_2) {
  io::SimPlugin p;
  const auto sz = p.add_device(vf66b_spec({{"j09", "4"}, {"j10", "15"}}));
  EXPECT_EQ(sz.output_bytes, 12u) << "instance 102: 6 words";
  EXPECT_EQ(sz.input_bytes, 8u) << "instance 140: 4 words";
  io::SimPlugin q;
  EXPECT_THROW(q.add_device(vf66b_spec({{"j10", "16"}})), io::ParamError);
  EXPECT_THROW(q.add_device(vf66b_spec({{"speed_scale", "3"}})), io::ParamError)
      << "unknown key (the setting is j11)";
}

TEST(Vf66bSimPlugin, AcDriveRunsTheDriveThroughThePlugin) {
  io::SimPlugin p;
  const auto sz = p.add_device(vf66b_spec({{"j09", "1"},
                                           {"j10", "1"},
                                           {"b10", "3"},
                                           {"b11", "3"},
                                           {"startup_time", "100ms"},
                                           {"accel_time", "2s"},
                                           {"top_speed_rpm", "1800"}}));
  p.start(io::ClockMode::Virtual);
  std::vector<std::uint8_t> in(sz.input_bytes), out(sz.output_bytes);
  AcDrive fb;
  fb.Port.bind(in, out, &p.link(0));
  fb.Enable = true;
  fb.RunFwd = true;
  fb.SpeedRef = 450;
  ScanContext ctx{TIME{}, 1ms, 0};
  bool reached = false;
  for (int i = 0; i < 2000 && !reached; ++i) {
    p.step(ctx.now, 1ms);
    p.latch_inputs(0, in);
    fb(ctx);
    p.publish_outputs(0, out);
    reached = fb.AtReference;
    ctx.now += 1ms;
  }
  ASSERT_TRUE(reached);
  EXPECT_DOUBLE_EQ(fb.ActualSpeed, 450);
  EXPECT_EQ(fb.State, DriveState::Enabled);
  p.stop();
}

}  // namespace plc::acdrive
