#include "plc/sim/nord_safety_functions.hpp"

#include <chrono>
#include <cmath>

namespace plc::sim {

namespace {
TIME seconds(double s) {
  return std::chrono::duration_cast<TIME>(std::chrono::duration<double>(s));
}
}  // namespace

void NordSafetyFunctions::reset() {
  st_ = {};
  trip_ = 0;
  status_ = {};
  idle_ = true;
}

bool NordSafetyFunctions::cause_present(int fn, double speed_rpm) const {
  const double n = std::abs(speed_rpm);
  switch (fn) {
    case kSls:
      return n > static_cast<double>(ip_.p823[trip_level_]);
    case kSsr:
      return n > static_cast<double>(ip_.p823[4]) || n < static_cast<double>(ip_.p823[5]);
    default:
      return false;
  }
}

void NordSafetyFunctions::step_functions(TIME now, TIME dt, const Request& rq, double speed_rpm,
                                         double position_inc) {
  const double n = std::abs(speed_rpm);
  bool any_active = false;
  for (int fn = 0; fn < kCount; ++fn) any_active |= ((enabled_ >> fn) & 1u) != 0 && rq.on[fn];
  if (!any_active && idle_) {  // the loop below would only write what is there
    status_[kCount] = n <= ssm_max_;
    return;
  }
  idle_ = !any_active;  // each function takes the inactive branch below
  const std::uint8_t lvl = rq.sls_level & 3u;
  // P821 / P822 element per function (SLS by level).
  const int act_idx[kCount] = {lvl, 4, 5, 6, 7};
  const int react_idx[kCount] = {lvl, 4, 5, 6, -1};

  for (int fn = 0; fn < kCount; ++fn) {
    State& s = st_[fn];
    const bool active = ip_.p820[fn] == 1 && rq.on[fn];
    if (active && !s.requested) s.since = now;
    s.requested = active;
    if (!active) {
      s.monitoring = false;
      s.integ = TIME{};
      status_[fn] = false;
      continue;
    }
    if (!s.monitoring && now - s.since >= seconds(ip_.p821_s[act_idx[fn]])) {
      s.monitoring = true;
      s.ref_pos = position_inc;
      s.last_pos = position_inc;
      s.wrong_way = 0.0;
      s.integ = TIME{};
    }
    bool violating = false;
    switch (fn) {
      case kSls:
        violating = n > static_cast<double>(ip_.p823[lvl]);
        break;
      case kSsr:
        violating = n > static_cast<double>(ip_.p823[4]) || n < static_cast<double>(ip_.p823[5]);
        break;
      case kSdiP:
      case kSdiN: {
        const double d = position_inc - s.last_pos;
        s.last_pos = position_inc;
        if ((fn == kSdiP && d < 0) || (fn == kSdiN && d > 0)) s.wrong_way += std::abs(d);
        violating = s.monitoring && s.wrong_way > static_cast<double>(ip_.p824[fn - kSdiP]);
        break;
      }
      case kSos:
        violating =
            s.monitoring && std::abs(position_inc - s.ref_pos) > static_cast<double>(ip_.p824[2]);
        break;
      default:
        break;
    }
    // Status bit: function active and within its limit (§2.4).
    if (fn == kSdiP) {
      status_[fn] = speed_rpm >= 0.0 && !violating;
    } else if (fn == kSdiN) {
      status_[fn] = speed_rpm <= 0.0 && !violating;
    } else {
      status_[fn] = !violating;
    }
    if (!s.monitoring) continue;
    if (violating) {
      s.integ += dt;
    } else {
      s.integ = s.integ > dt ? s.integ - dt : TIME{};
    }
    const TIME reaction = react_idx[fn] < 0 ? TIME{} : seconds(ip_.p822_s[react_idx[fn]]);
    if (violating && s.integ >= reaction && !tripped(fn)) {
      trip_ = static_cast<std::uint8_t>(trip_ | (1u << fn));
      if (fn == kSls) trip_level_ = lvl;
    }
  }
  status_[kCount] = n <= ssm_max_;
}

}  // namespace plc::sim
