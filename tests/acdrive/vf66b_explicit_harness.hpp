// A simulated VF66B answering explicit services (query_record, the mapping
// of plc/io/explicit_message.hpp) in 1 ms virtual-time steps, for the
// explicit-service tests. Requests are literal bytes in the 8/8 body format
// (toyo-vf66-devicenet.md §1.4): class, instance, attribute, data.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "acdrive_test_util.hpp"
#include "plc/io/explicit_message.hpp"
#include "vf66b/vf66b_model.hpp"

namespace plc::sim::test {

using namespace std::chrono_literals;
using Bytes = std::vector<std::uint8_t>;

struct Answer {
  io::RecordError error = io::RecordError::None;
  Bytes data;
  // The §11.1 general status of an Error Response, 0 for success.
  [[nodiscard]] int general() const {
    const auto c = static_cast<std::uint16_t>(error);
    return c >= 0x100 ? (c >> 8) : (c == 0 ? 0 : -static_cast<int>(c));
  }
};

struct Drive {
  explicit Drive(unsigned j09 = 1, unsigned j10 = 1) : Drive(acdrive::test::net_config(j09, j10)) {}
  explicit Drive(const Vf66bConfig& c) {
    m = std::make_unique<Vf66bModel>(c);
    out.assign(m->output_size(), 0);
    in.assign(m->input_size(), 0);
    step(20);
  }
  // Steps as the sim plugin does: every step consumes `out` as a new output
  // message.
  void step(int n = 1) {
    for (int i = 0; i < n; ++i) {
      now += 1ms;
      m->step(now, 1ms, out, in);
    }
  }
  // Steps as a DeviceNet slave does between two poll commands: no new
  // output message.
  void idle(int n = 1) {
    for (int i = 0; i < n; ++i) {
      now += 1ms;
      m->step_io(now, 1ms, out, false, in);
    }
  }
  Answer call(std::uint16_t index, const Bytes& req) {
    std::array<std::uint8_t, io::kRecordMaxBytes> buf{};
    std::size_t len = 0;
    Answer a;
    a.error = m->query_record(index, req, buf, len);
    a.data.assign(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(len));
    return a;
  }
  Answer get(std::uint8_t cls, std::uint8_t inst, std::uint8_t attr) {
    return call(0xD00E, {cls, inst, attr});
  }
  Answer set(std::uint8_t cls, std::uint8_t inst, std::uint8_t attr, const Bytes& data) {
    Bytes req = {cls, inst, attr};
    req.insert(req.end(), data.begin(), data.end());
    return call(0xD010, req);
  }
  std::unique_ptr<Vf66bModel> m;
  Bytes out, in;
  TIME now{};
};

}  // namespace plc::sim::test
