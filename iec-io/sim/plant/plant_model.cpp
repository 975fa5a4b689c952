#include "plant/plant_model.hpp"

#include <cmath>

namespace plc::plant {
namespace {

using std::chrono::hours;
using std::chrono::microseconds;
using std::chrono::milliseconds;
using std::chrono::minutes;

// The four ways to give the dynamics, by the keys that select them.
ContinuousModel dynamics(const io::ModelParams& p) {
  const bool ss = p.has("A") || p.has("B") || p.has("C") || p.has("D");
  const bool tf = p.has("num") || p.has("den");
  const bool lag = p.has("tau") || p.has("tau2");
  const bool osc = p.has("wn") || p.has("zeta");
  const int forms = int(ss) + int(tf) + int(lag) + int(osc);
  const char* kWays =
      "give the dynamics one way: A, B, C (and D); num and den; gain and tau (and tau2); or "
      "gain, wn and zeta";
  if (forms == 0) throw io::ParamError("", std::string("the plant has no dynamics: ") + kWays);
  if (forms > 1) {
    const char* second = osc   ? (p.has("wn") ? "wn" : "zeta")
                         : lag ? (p.has("tau") ? "tau" : "tau2")
                               : (p.has("num") ? "num" : "den");
    throw io::ParamError(second, std::string("more than one form of dynamics: ") + kWays);
  }
  if ((ss || tf) && p.has("gain"))
    throw io::ParamError("gain",
                         "gain belongs to the tau and wn/zeta forms; with A..D or num/den "
                         "the gain is in the matrices or coefficients");
  auto need_matrix = [&](const char* k) {
    auto m = p.get_matrix(k);
    if (!m)
      throw io::ParamError(k, std::string("missing ") + k + " (state space needs A, B and C)");
    return *m;
  };
  auto need_list = [&](const char* k) {
    auto l = p.get_list(k);
    if (!l)
      throw io::ParamError(
          k, std::string("missing ") + k + " (a transfer function needs num and den)");
    return *l;
  };
  auto seconds_of = [&](const char* k, bool required) {
    if (required && !p.has(k)) throw io::ParamError(k, std::string("missing ") + k);
    return std::chrono::duration<double>(p.get_time(k, TIME(0), microseconds(1), hours(24 * 365)))
        .count();
  };
  if (ss) {
    const auto a = need_matrix("A"), b = need_matrix("B"), c = need_matrix("C");
    const auto d = p.get_matrix("D");
    return state_space(a, b, c, d ? *d : Rows{});
  }
  if (tf) return transfer_function(need_list("num"), need_list("den"));
  const double gain = p.get_double("gain", 1.0, -1e12, 1e12);
  if (lag) {
    const double t1 = seconds_of("tau", true);
    if (!p.has("tau2")) return first_order(gain, t1);
    return second_order(gain, t1, seconds_of("tau2", true));
  }
  if (!p.has("wn")) throw io::ParamError("zeta", "missing wn (natural frequency, rad/s)");
  if (!p.has("zeta")) throw io::ParamError("wn", "missing zeta (damping ratio)");
  return second_order_oscillating(gain, p.get_double("wn", 1, 1e-9, 1e9),
                                  p.get_double("zeta", 1, 0, 1e6));
}

io::ByteOrder byte_order(const io::ModelParams& p, const std::string& key, io::ByteOrder def) {
  const std::string v = p.get_string(key, def == io::ByteOrder::Big ? "big" : "little");
  if (v == "big") return io::ByteOrder::Big;
  if (v == "little") return io::ByteOrder::Little;
  throw io::ParamError(key, "byte order is big or little, not '" + v + "'");
}

// `from`/`to` with their `area` and `byte`.
ChannelPlace place(const io::ModelParams& p, const std::string& prefix, const char* device_key,
                   bool input) {
  ChannelPlace pl;
  const std::string dev_key = prefix + "." + device_key;
  pl.device = p.get_string(dev_key, "");
  const std::string area_key = prefix + ".area", byte_key = prefix + ".byte";
  if (pl.device.empty()) {
    if (p.has(area_key) || p.has(byte_key))
      throw io::ParamError(p.has(area_key) ? area_key : byte_key,
                           "area and byte place a channel in another device: give " + dev_key +
                               " too (without it the channel is in the plant's own process data)");
    return pl;
  }
  if (!p.has(byte_key))
    throw io::ParamError(dev_key,
                         "give " + byte_key + ", where the value is in " + pl.device + "'s bytes");
  pl.byte = static_cast<std::size_t>(p.get_int(byte_key, 0, 0, 65535));
  if (input) {
    if (!p.has(area_key))
      throw io::ParamError(dev_key, "give " + area_key + ": inputs (what " + pl.device +
                                        " sends the PLC) or outputs (what the PLC sends it)");
    const std::string area = p.get_string(area_key, "");
    if (area != "inputs" && area != "outputs")
      throw io::ParamError(area_key, "area is inputs or outputs, not '" + area + "'");
    pl.peer_outputs = area == "outputs";
  } else if (p.has(area_key)) {
    // The PLC overwrites a device's outputs every scan: a plant can only
    // stand in for a sensor, i.e. write a device's inputs.
    if (p.get_string(area_key, "") != "inputs")
      throw io::ParamError(area_key, "a plant output goes into another device's inputs only");
  }
  return pl;
}

}  // namespace

PlantModel::PlantModel(const io::ModelParams& p)
    : noise_(static_cast<std::uint64_t>(p.get_int("seed", 1, 0, INT64_MAX))) {
  ContinuousModel m;
  try {
    m = dynamics(p);
  } catch (const PlantError& e) {
    throw io::ParamError(e.field, e.what());
  }
  h_ = p.get_time("sample", milliseconds(1), microseconds(1), minutes(1));
  const io::ByteOrder order = byte_order(p, "byte_order", io::ByteOrder::Big);
  const TIME plant_dead = p.get_time("dead_time", TIME(0), TIME(0), hours(24));
  const int n = m.states(), k = m.inputs(), q = m.outputs();

  // Channels u1..um, y1..yp; a channel beyond the plant's size is a typo
  // or a plant that lost an input, said so instead of "unknown parameter".
  for (int i = k + 1; i <= 8 + 1; ++i)
    if (p.has_group("u" + std::to_string(i)))
      throw io::ParamError("u" + std::to_string(i), "the plant has " + std::to_string(k) +
                                                        " input(s) (columns of B), no u" +
                                                        std::to_string(i));
  for (int i = q + 1; i <= 8 + 1; ++i)
    if (p.has_group("y" + std::to_string(i)))
      throw io::ParamError("y" + std::to_string(i), "the plant has " + std::to_string(q) +
                                                        " output(s) (rows of C), no y" +
                                                        std::to_string(i));
  DiscretiseOptions opt;
  opt.allow_unstable = p.get_bool("allow_unstable", false);
  std::vector<std::string> dead_keys;
  for (int i = 1; i <= k; ++i) {
    Input in;
    in.key = "u" + std::to_string(i);
    in.codec = parse_codec(p, in.key, order);
    in.place = place(p, in.key, "from", true);
    if (in.place.device.empty()) {
      in.place.byte = out_size_;
      out_size_ += type_size(in.codec.type);
    }
    const std::string dk = in.key + ".dead_time";
    opt.dead_time.push_back(p.get_time(dk, plant_dead, TIME(0), hours(24)));
    dead_keys.push_back(p.has(dk) ? dk : "dead_time");
    if (opt.dead_time.back() / h_ > kMaxDelaySamples)
      throw io::ParamError(dead_keys.back(),
                           "the dead time is " + std::to_string(opt.dead_time.back() / h_) +
                               " samples, at most " + std::to_string(kMaxDelaySamples) +
                               " (choose a longer sample or a shorter dead time)");
    inputs_.push_back(std::move(in));
  }
  for (int i = 1; i <= q; ++i) {
    Output out;
    out.key = "y" + std::to_string(i);
    out.codec = parse_codec(p, out.key, order);
    out.place = place(p, out.key, "to", false);
    out.offset = p.get_double(out.key + ".offset", 0, -1e12, 1e12);
    out.noise = p.get_double(out.key + ".noise", 0, 0, 1e12);
    if (out.place.device.empty()) {
      out.place.byte = in_size_;
      in_size_ += type_size(out.codec.type);
    }
    outputs_.push_back(std::move(out));
  }
  DiscreteModel d;
  try {
    d = discretise_zoh(m, h_, opt);
  } catch (const PlantError& e) {
    throw io::ParamError(e.field, e.what());
  }
  plant_ = std::make_unique<LinearPlant>(d);
  if (auto x0 = p.get_list("x0")) {
    if (static_cast<int>(x0->size()) != n)
      throw io::ParamError("x0", "x0 has " + std::to_string(x0->size()) +
                                     " values, the plant has " + std::to_string(n) + " state(s)");
    plant_->set_state(*x0);
  }
  u_.assign(static_cast<std::size_t>(k), 0.0);
  y_meas_.assign(static_cast<std::size_t>(q), 0.0);
  p.reject_unknown();
}

bool PlantModel::needs_peers() const {
  for (const auto& i : inputs_)
    if (!i.place.device.empty()) return true;
  for (const auto& o : outputs_)
    if (!o.place.device.empty()) return true;
  return false;
}

void PlantModel::bind_peers(const io::DevicePeers& peers) {
  auto bind = [&](ChannelPlace& pl, const ChannelCodec& c, const std::string& key,
                  const char* device_key) {
    if (pl.device.empty()) return;
    const auto peer = peers.find(pl.device);
    if (!peer) {
      std::string names;
      for (const auto& nm : peers.names()) names += (names.empty() ? "" : ", ") + nm;
      throw io::ParamError(key + "." + device_key,
                           "no device '" + pl.device +
                               "' before this one in the same sim plugin (a plant couples to "
                               "devices listed above it; here: " +
                               (names.empty() ? "none" : names) + ")");
    }
    const std::span<std::uint8_t> area = pl.peer_outputs ? peer->outputs : peer->inputs;
    if (pl.byte + type_size(c.type) > area.size())
      throw io::ParamError(key + ".byte", "byte " + std::to_string(pl.byte) + " + " +
                                              std::to_string(type_size(c.type)) +
                                              " bytes is beyond " + pl.device + "'s " +
                                              (pl.peer_outputs ? "outputs" : "inputs") + " (" +
                                              std::to_string(area.size()) + " bytes)");
    pl.bytes = area;
  };
  for (auto& i : inputs_) bind(i.place, i.codec, i.key, "from");
  for (auto& o : outputs_) bind(o.place, o.codec, o.key, "to");
}

void PlantModel::step(TIME, TIME dt, std::span<const std::uint8_t> from_plc,
                      std::span<std::uint8_t> to_plc) {
  // Inputs once per step: they hold over it (zero-order hold). A coupling
  // a host never bound reads 0.
  for (std::size_t i = 0; i < inputs_.size(); ++i) {
    const Input& in = inputs_[i];
    const std::uint8_t* src = nullptr;
    if (in.place.device.empty()) {
      if (in.place.byte + type_size(in.codec.type) <= from_plc.size())
        src = from_plc.data() + in.place.byte;
    } else if (!in.place.bytes.empty()) {
      src = in.place.bytes.data() + in.place.byte;
    }
    const double v = src ? in.codec.decode(src) : 0.0;
    // A NaN from a REAL source would poison the state for good: it counts
    // as 0 (the signal is broken, the plant is not).
    u_[i] = std::isfinite(v) ? v : 0.0;
  }
  bool sampled = false;
  if (!diverged_) {
    pending_ += dt;
    while (pending_ >= h_) {
      plant_->step(u_);
      pending_ -= h_;
      sampled = true;
    }
  }
  if (sampled || !measured_) {
    const auto y = plant_->outputs();
    bool finite = true;
    for (double v : y) finite = finite && std::isfinite(v);
    if (!finite) {
      diverged_ = true;
    } else {
      for (std::size_t i = 0; i < outputs_.size(); ++i) {
        const Output& o = outputs_[i];
        y_meas_[i] = y[i] + o.offset + (o.noise > 0 ? o.noise * noise_.gaussian() : 0.0);
      }
      measured_ = true;
    }
  }
  if (!measured_) return;
  for (std::size_t i = 0; i < outputs_.size(); ++i) {
    const Output& o = outputs_[i];
    std::uint8_t* dst = nullptr;
    if (o.place.device.empty()) {
      if (o.place.byte + type_size(o.codec.type) <= to_plc.size())
        dst = to_plc.data() + o.place.byte;
    } else if (!o.place.bytes.empty()) {
      dst = o.place.bytes.data() + o.place.byte;
    }
    if (dst) o.codec.encode(y_meas_[i], dst);
  }
}

PLC_REGISTER_DEVICE_MODEL("plant", PlantModel)

}  // namespace plc::plant
