// The sim plugin's `plant` model: its process data (S7 analog words and
// other types, scaling, saturation, offset), noise from a seed, its own
// sample time, dead time from the config, a step that never allocates,
// located config errors (docs/config.md, "The plant model"), and couplings
// to other devices of the same sim plugin in a defined order.
#include <gtest/gtest.h>

#include <cmath>

#include "allocation_counter.hpp"
#include "plant/plant_model.hpp"
#include "plc/cell_config.hpp"
#include "plc/fb/acdrive/ac_drive.hpp"
#include "plc/io/byte_order.hpp"
#include "plc/io/sim_plugin.hpp"
#include "plc/runtime.hpp"

namespace pl = plc::plant;
namespace io = plc::io;
using namespace std::chrono_literals;
using plc::TIME;

namespace {

io::ModelParams params(std::initializer_list<std::pair<const char*, const char*>> kv) {
  io::ModelParams p;
  for (const auto& [k, v] : kv) p.set(k, v);
  return p;
}

// A plant model with its own process data buffers, stepped by hand.
struct Bench {
  pl::PlantModel m;
  std::vector<std::uint8_t> q, i;  // PLC -> plant, plant -> PLC
  TIME now{};
  explicit Bench(const io::ModelParams& p) : m(p), q(m.output_size()), i(m.input_size()) {}
  void step(TIME dt = 1ms, int n = 1) {
    for (int k = 0; k < n; ++k) {
      now += dt;
      m.step(now, dt, q, i);
    }
  }
  std::int16_t in_int(std::size_t byte) const { return io::load_be<std::int16_t>(i, byte); }
};

TEST(PlantModel, FirstOrderThroughS7AnalogWords) {
  // gain 1.5, tau 2 s; u1 and y1 default to INT 0..27648 = 0..100 %.
  Bench b(params({{"gain", "1.5"}, {"tau", "2s"}}));
  ASSERT_EQ(b.m.output_size(), 2u);
  ASSERT_EQ(b.m.input_size(), 2u);
  io::store_be<std::int16_t>(b.q, 0, 13824);  // 50 %
  for (int k = 1; k <= 6000; ++k) {
    b.step();
    const double pct = 75.0 * (1 - std::exp(-k * 1e-3 / 2.0));
    ASSERT_EQ(b.in_int(0), std::lround(pct * 276.48)) << "t=" << k << "ms";
  }
  // Full heater: 150 % would be the plant's answer, the transmitter
  // saturates at 100 %.
  io::store_be<std::int16_t>(b.q, 0, 27648);
  b.step(1ms, 20000);
  EXPECT_EQ(b.in_int(0), 27648);
  EXPECT_GT(b.m.plant().outputs()[0], 140.0);
  // And the actuator saturates too: 32767 counts as 100 %, not 118.5 %.
  io::store_be<std::int16_t>(b.q, 0, 32767);
  b.step(1ms, 20000);
  EXPECT_NEAR(b.m.plant().outputs()[0], 150.0, 1e-6);
}

TEST(PlantModel, ChannelTypesScalingOffsetAndSaturation) {
  // A REAL actuator in % saturated to 0..80, a temperature as INT 0..300
  // degC on 0..27648 with 20 degC ambient, and a REAL copy little-endian.
  Bench b(params({{"A", "[[-0.5]]"},
                  {"B", "[[1]]"},
                  {"C", "[[1], [1]]"},
                  {"u1.type", "REAL"},
                  {"u1.min", "0"},
                  {"u1.max", "80"},
                  {"y1.eng", "[0, 300]"},
                  {"y1.offset", "20"},
                  {"y2.type", "REAL"},
                  {"y2.order", "little"},
                  {"y2.offset", "20"}}));
  ASSERT_EQ(b.m.output_size(), 4u);
  ASSERT_EQ(b.m.input_size(), 6u);
  b.step();
  EXPECT_EQ(b.in_int(0), 1843);  // 20 / 300 x 27648 = 1843.2
  EXPECT_EQ(io::load<float>(b.i.data() + 2, io::ByteOrder::Little), 20.0f);
  io::store<float>(b.q.data(), 100.0f, io::ByteOrder::Big);
  b.step(1ms, 60000);  // 60 s: x -> 2 u = 160 (u limited to 80)
  EXPECT_NEAR(io::load<float>(b.i.data() + 2, io::ByteOrder::Little), 180.0f, 0.01f);
  EXPECT_EQ(b.in_int(0), std::lround(180.0 / 300.0 * 27648));
}

TEST(PlantModel, NoiseIsSeededAndDeterministic) {
  auto p = [](const char* seed) {
    return params(
        {{"gain", "1"}, {"tau", "1s"}, {"y1.type", "REAL"}, {"y1.noise", "0.5"}, {"seed", seed}});
  };
  Bench a(p("7")), b(p("7")), c(p("8"));
  double sum = 0, sq = 0;
  bool differ = false;
  for (int k = 0; k < 20000; ++k) {
    a.step();
    b.step();
    c.step();
    ASSERT_EQ(a.i, b.i) << "same seed, different bytes at step " << k;
    differ = differ || a.i != c.i;
    const double v = io::load_be<float>(a.i, 0);
    sum += v;
    sq += v * v;
  }
  EXPECT_TRUE(differ);
  const double mean = sum / 20000, sigma = std::sqrt(sq / 20000 - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.02);
  EXPECT_NEAR(sigma, 0.5, 0.02);
}

TEST(PlantModel, OwnSampleTimeAndDeadTime) {
  // sample 5 ms on 1 ms steps: the output moves every fifth step; 100 ms
  // dead time: nothing before it.
  Bench b(params({{"gain", "1"},
                  {"tau", "1s"},
                  {"sample", "5ms"},
                  {"dead_time", "100ms"},
                  {"y1.type", "REAL"}}));
  io::store_be<std::int16_t>(b.q, 0, 27648);
  float last = 0;
  int changes = 0;
  for (int k = 1; k <= 400; ++k) {
    b.step();
    const float y = io::load_be<float>(b.i, 0);
    if (k <= 100) {
      ASSERT_EQ(y, 0.0f) << "before the dead time, step " << k;
    }
    if (y != last) {
      ++changes;
      EXPECT_EQ(k % 5, 0) << "moved between samples at step " << k;
    }
    last = y;
  }
  EXPECT_EQ(changes, 60);
  EXPECT_NEAR(last, 100.0 * (1 - std::exp(-0.3)), 1e-4);
}

TEST(PlantModel, StepAllocatesNothing) {
  if (!plant_test::counting()) GTEST_SKIP() << "a sanitizer owns malloc";
  Bench b(params(
      {{"num", "[1]"}, {"den", "[1, 3, 3, 1]"}, {"dead_time", "250ms"}, {"y1.noise", "0.1"}}));
  io::store_be<std::int16_t>(b.q, 0, 10000);
  b.step();
  const std::size_t before = plant_test::allocations();
  b.step(1ms, 10000);
  EXPECT_EQ(plant_test::allocations(), before);
}

// ---- in a cell: located errors and couplings ----

const char* kCell = R"(cell: t
clock: virtual
image: {inputs: 64, outputs: 64, memory: 8, byte_order: big}
tasks:
  - {name: main, period: 1ms, programs: []}
plugins:
  - {name: sim, type: sim}
devices:
  - name: tank1
    plugin: sim
    model: first_order
    input: "%IB0"
    output: "%QB0"
    params: {tau: 1s}
  - name: card
    plugin: sim
    model: loopback
    input: "%IB4"
    output: "%QB4"
    params: {size: 4}
  - name: oven
    plugin: sim
    model: plant
    input: "%IB16"
    output: "%QB16"
    params:
PARAMS
)";

std::string cell(const std::string& params_block) {
  std::string s = kCell;
  s.replace(s.find("PARAMS"), 6, params_block);
  return s;
}

std::string config_error(const std::string& yaml) {
  try {
    plc::Runtime rt(plc::parse_cell_config(yaml, "test.yaml"));
  } catch (const plc::ConfigError& e) {
    return e.what();
  }
  return "no error";
}

struct ErrorCase {
  const char* name;
  const char* params;  // indented 6 spaces, from line 27 of the cell
  const char* where;   // "test.yaml:LINE:COLUMN"
  const char* says;
};

void PrintTo(const ErrorCase& c, std::ostream* os) { *os << c.name; }

class PlantConfigErrors : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(PlantConfigErrors, NameFileLineAndKey) {
  const auto& c = GetParam();
  const std::string msg = config_error(cell(c.params));
  EXPECT_EQ(msg.rfind(c.where, 0), 0u) << msg;
  EXPECT_NE(msg.find(c.says), std::string::npos) << msg;
}

INSTANTIATE_TEST_SUITE_P(
    Plant, PlantConfigErrors,
    ::testing::Values(
        ErrorCase{"BWithTooFewRows",
                  "      A: [[-1, 0], [0, -2]]\n      B: [[1]]\n      C: [[1, 0]]",
                  "test.yaml:28:7:",
                  "device 'oven': key 'B': B is 1x1 but A is 2x2: B needs one row per state (2)"},
        ErrorCase{"RaggedMatrix", "      A: [[-1, 0], [0]]\n      B: [[1], [1]]\n      C: [[1, 0]]",
                  "test.yaml:27:7:", "key 'A': A row 2 has 1 entries, row 1 has 2"},
        ErrorCase{"NotANumberInAMatrix", "      A: [[-1, x]]\n      B: [[1]]\n      C: [[1]]",
                  "test.yaml:27:7:", "key 'A': 'x' is not a finite number"},
        ErrorCase{"Unstable", "      A: [[0.2]]\n      B: [[1]]\n      C: [[1]]", "test.yaml:27:7:",
                  "key 'A': the plant is unstable: A has an eigenvalue with real part 0.2"},
        ErrorCase{"NonFiniteDiscretisation",
                  "      A: [[50]]\n      B: [[1]]\n      C: [[1]]\n      allow_unstable: true\n"
                  "      sample: 20s",
                  "test.yaml:27:7:", "key 'A': the discretised plant is not finite"},
        ErrorCase{"TwoFormsOfDynamics",
                  "      gain: 2\n      tau: 3s\n      num: [1]\n      den: [1, 1]",
                  "test.yaml:28:7:", "key 'tau': more than one form of dynamics"},
        ErrorCase{"NoDynamics", "      seed: 3", "test.yaml:27:7:", "the plant has no dynamics"},
        ErrorCase{"ChannelThePlantDoesNotHave", "      tau: 3s\n      u2: {type: REAL}",
                  "test.yaml:28:7:", "key 'u2': the plant has 1 input(s) (columns of B), no u2"},
        ErrorCase{"UnknownChannelType", "      tau: 3s\n      y1: {type: FLOAT}",
                  "test.yaml:28:12:", "key 'y1.type': unknown type 'FLOAT'"},
        ErrorCase{"UnknownPeer", "      tau: 3s\n      u1: {from: pump, area: inputs, byte: 0}",
                  "test.yaml:28:12:",
                  "key 'u1.from': no device 'pump' before this one in the same sim plugin (a plant "
                  "couples to devices listed above it; here: tank1, card)"},
        ErrorCase{"PeerByteBeyondItsData",
                  "      tau: 3s\n      u1: {from: tank1, area: inputs, byte: 3}",
                  "test.yaml:28:39:",
                  "key 'u1.byte': byte 3 + 2 bytes is beyond tank1's inputs (4 bytes)"},
        ErrorCase{"PeerWithoutArea", "      tau: 3s\n      u1: {from: tank1, byte: 0}",
                  "test.yaml:28:12:", "give u1.area: inputs (what tank1 sends the PLC) or outputs"},
        ErrorCase{"DeadTimeTooLong", "      tau: 3s\n      sample: 1us\n      dead_time: 2s",
                  "test.yaml:29:7:", "key 'dead_time': the dead time is 2000000 samples"},
        ErrorCase{"UnknownKey", "      tau: 3s\n      tua: 2s",
                  "test.yaml:28:7:", "unknown parameter 'tua'"},
        // The config loader's nesting (runtime/src/cell_config.cpp): two
        // levels of mappings, lists of numbers or of lists.
        ErrorCase{"NestsTooDeep", "      tau: 3s\n      u1: {type: {a: {b: 1}}}",
                  "test.yaml:28:22:", "parameter 'u1.type.a' nests too deep"},
        ErrorCase{"ListOfMappings", "      tau: 3s\n      x0: [{a: 1}]",
                  "test.yaml:28:12:", "parameter 'x0': a list holds values or lists of values"},
        ErrorCase{"ListTooDeep", "      tau: 3s\n      x0: [[[1]]]",
                  "test.yaml:28:13:", "parameter 'x0': a list holds values or lists of values"}));

// The sim plugin with tank1 (first_order), card (loopback, 4 bytes) and the
// plant last, stepped by hand as the runtime does in virtual time:
// publish the PLC's outputs, step, latch the inputs.
struct Cell {
  io::SimPlugin sim;
  std::vector<std::vector<std::uint8_t>> q, i;  // per device
  TIME now{};
  explicit Cell(const io::ModelParams& plant) {
    add("tank1", "first_order", params({{"tau", "1s"}}));
    add("card", "loopback", params({{"size", "4"}}));
    add("oven", "plant", plant);
    sim.start(io::ClockMode::Virtual);
  }
  void add(const char* name, const char* model, const io::ModelParams& p) {
    const auto sizes = sim.add_device({name, model, p});
    q.emplace_back(sizes.output_bytes);
    i.emplace_back(sizes.input_bytes);
  }
  void tick() {
    for (std::size_t d = 0; d < q.size(); ++d) sim.publish_outputs(d, q[d]);
    now += 1ms;
    sim.step(now, 1ms);
    for (std::size_t d = 0; d < i.size(); ++d) sim.latch_inputs(d, i[d]);
  }
};

TEST(PlantCell, ReadsAnotherDevicesInputsAndOutputsInTheSameStep) {
  // The plant reads tank1's level (its input bytes, INT) and the PLC's
  // valve command to tank1 (its output bytes), and passes both through D
  // as REALs: within one step it sees what tank1 delivered in that step
  // and what the PLC published to it, so the PLC reads equal values.
  Cell c(params({{"A", "[[-1]]"},
                 {"B", "[[0, 0]]"},
                 {"C", "[[0], [0]]"},
                 {"D", "[[1, 0], [0, 1]]"},
                 {"u1.from", "tank1"},
                 {"u1.area", "inputs"},
                 {"u1.byte", "0"},
                 {"u2.from", "tank1"},
                 {"u2.area", "outputs"},
                 {"u2.byte", "0"},
                 {"y1.type", "REAL"},
                 {"y2.type", "REAL"}}));
  ASSERT_EQ(c.q[2].size(), 0u);  // no input from the PLC
  for (int k = 0; k < 3000; ++k) {
    const std::int16_t valve = k < 1500 ? 20000 : 5000;
    io::store_be<std::int16_t>(c.q[0], 0, valve);
    c.tick();
    const double level = io::load_be<std::int16_t>(c.i[0], 0) / 276.48;
    ASSERT_NEAR(io::load_be<float>(c.i[2], 0), level, 1e-4) << "tick " << k;
    ASSERT_NEAR(io::load_be<float>(c.i[2], 4), valve / 276.48, 1e-4) << "tick " << k;
  }
}

TEST(PlantCell, WritesIntoAnotherDevicesInputs) {
  // y1 goes into the loopback card's input bytes 2..3, after the card
  // stepped (it echoes its outputs there otherwise): the PLC reads the
  // plant's value there, not the echo.
  Cell c(params(
      {{"gain", "1"}, {"tau", "100ms"}, {"x0", "[50]"}, {"y1.to", "card"}, {"y1.byte", "2"}}));
  EXPECT_EQ(c.i[2].size(), 0u);
  io::store_be<std::int16_t>(c.q[1], 0, 1111);
  io::store_be<std::int16_t>(c.q[1], 2, 2222);
  for (int k = 1; k <= 50; ++k) {
    c.tick();
    EXPECT_EQ(io::load_be<std::int16_t>(c.i[1], 0), 1111);
    EXPECT_EQ(io::load_be<std::int16_t>(c.i[1], 2), std::lround(13824 * std::exp(-k * 0.001 / 0.1)))
        << "tick " << k;
  }
}

TEST(PlantCell, Vf66bSpeedDrivesAConveyorLoad) {
  // The issue's example: a conveyor belt (first order, 0.5 s, 1 mm/s per
  // r/min through its gearbox) driven by the simulated VF66B's actual speed
  // (input assembly 71, bytes 2..3, r/min x 2^3, little-endian: DeviceNet),
  // which AcDrive runs at 450 r/min. The belt's speed is a REAL to the PLC.
  io::SimPlugin sim;
  io::DeviceSpec drive{"conveyor", "vf66b", {}};
  for (const auto& [k, v] : {std::pair{"j09", "1"},
                             {"j10", "1"},
                             {"b10", "3"},
                             {"b11", "3"},
                             {"startup_time", "100ms"},
                             {"accel_time", "2s"},
                             {"top_speed_rpm", "1800"}})
    drive.params.set(k, v);
  const auto dsz = sim.add_device(drive);
  const auto bsz = sim.add_device({"belt", "plant",
                                   params({{"gain", "0.001"},
                                           {"tau", "500ms"},
                                           {"u1.from", "conveyor"},
                                           {"u1.area", "inputs"},
                                           {"u1.byte", "2"},
                                           {"u1.order", "little"},
                                           {"u1.raw", "[0, 14400]"},
                                           {"u1.eng", "[0, 1800]"},
                                           {"y1.type", "REAL"}})});
  ASSERT_EQ(bsz.output_bytes, 0u);
  sim.start(io::ClockMode::Virtual);
  std::vector<std::uint8_t> din(dsz.input_bytes), dout(dsz.output_bytes), belt(bsz.input_bytes);
  plc::acdrive::AcDrive fb;
  fb.Port.bind(din, dout, &sim.link(0));
  fb.Enable = true;
  fb.RunFwd = true;
  fb.SpeedRef = 450;
  plc::ScanContext ctx{TIME{}, 1ms, 0};
  double speed_at_reference = -1;
  for (int i = 0; i < 8000; ++i) {
    sim.step(ctx.now, 1ms);
    sim.latch_inputs(0, din);
    sim.latch_inputs(1, belt);
    fb(ctx);
    sim.publish_outputs(0, dout);
    if (fb.AtReference && speed_at_reference < 0) speed_at_reference = io::load_be<float>(belt, 0);
    ctx.now += 1ms;
  }
  ASSERT_TRUE(fb.AtReference);
  // While the drive ramped (0 -> 450 r/min in 0.5 s) the belt lagged it by
  // its 0.5 s: behind 0.45 m/s when the drive got there, then on it.
  EXPECT_GT(speed_at_reference, 0.1);
  EXPECT_LT(speed_at_reference, 0.4);
  EXPECT_NEAR(io::load_be<float>(belt, 0), 0.45, 1e-4);
  sim.stop();
}

TEST(PlantCell, SameConfigSameBytes) {
  // Two runs of the cell with a noisy plant coupled to tank1's level:
  // identical bytes at every tick.
  auto record = [] {
    Cell c(params({{"num", "[2]"},
                   {"den", "[4, 4, 1]"},
                   {"dead_time", "30ms"},
                   {"u1.from", "tank1"},
                   {"u1.area", "inputs"},
                   {"u1.byte", "0"},
                   {"y1.noise", "0.3"},
                   {"seed", "11"}}));
    std::vector<std::uint8_t> all;
    for (int k = 0; k < 5000; ++k) {
      io::store_be<std::int16_t>(c.q[0], 0, (k / 700) % 2 ? 27648 : 3000);
      c.tick();
      all.insert(all.end(), c.i[2].begin(), c.i[2].end());
    }
    return all;
  };
  const auto a = record(), b = record();
  EXPECT_TRUE(a == b);
}

}  // namespace
