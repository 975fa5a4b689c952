#include "trend_layout.hpp"

#include <algorithm>
#include <cmath>

#include "plc/types.hpp"

namespace plc::hmi {

std::optional<TrendClass> trend_class(std::string_view iec_type) {
  for (int i = 0; i <= int(VarType::STRING); ++i) {
    const auto t = static_cast<VarType>(i);
    if (iec_type != to_string(t)) continue;
    switch (t) {
      case VarType::BOOL:
        return TrendClass::Bool;
      case VarType::REAL:
      case VarType::LREAL:
        return TrendClass::Real;
      case VarType::TIME:
        return TrendClass::Time;
      case VarType::STRING:
        return std::nullopt;
      default:
        return TrendClass::Integer;  // signed, unsigned and bit strings
    }
  }
  return std::nullopt;
}

namespace {

constexpr double kBoolLane = 1.5;  // a 0/1 lane and the gap to the next

const char* label_of(TrendClass c) {
  switch (c) {
    case TrendClass::Bool:
      return "BOOL";
    case TrendClass::Integer:
      return "integer";
    case TrendClass::Real:
      return "REAL";
    case TrendClass::Time:
      return "TIME (s)";
  }
  return "";
}

}  // namespace

std::vector<TrendPanel> trend_panels(const Trend& tr) {
  std::vector<TrendPanel> panels;
  for (TrendClass c : {TrendClass::Bool, TrendClass::Integer, TrendClass::Real, TrendClass::Time}) {
    TrendPanel p;
    p.cls = c;
    p.y_label = label_of(c);
    p.stepped = c == TrendClass::Bool || c == TrendClass::Integer;
    for (std::size_t k = 0; k < tr.names.size(); ++k)
      if (k < tr.types.size() && trend_class(tr.types[k]) == c) p.series.push_back(k);
    if (p.series.empty()) continue;
    if (c == TrendClass::Bool) {
      const std::size_t n = p.series.size();
      for (std::size_t j = 0; j < n; ++j) p.offset.push_back(kBoolLane * double(n - 1 - j));
      p.ymin = -0.25;
      p.ymax = kBoolLane * double(n);  // room for the top lane's name
    } else {
      p.offset.assign(p.series.size(), 0.0);
      double lo = INFINITY, hi = -INFINITY;
      for (std::size_t k : p.series)
        for (double y : tr.value[k])
          if (std::isfinite(y)) {
            lo = std::min(lo, y);
            hi = std::max(hi, y);
          }
      if (!std::isfinite(lo)) {  // no sample yet: an empty panel around 0
        lo = 0;
        hi = 0;
      }
      if (hi - lo < 1e-12) {
        lo -= 1;
        hi += 1;
      }
      const double pad = (hi - lo) * 0.05;
      p.ymin = lo - pad;
      p.ymax = hi + pad;
    }
    panels.push_back(std::move(p));
  }
  return panels;
}

TrendLine trend_line(const std::vector<double>& t, const std::vector<double>& v, bool stepped,
                     double t_end) {
  TrendLine l;
  const std::size_t n = std::min(t.size(), v.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) continue;
    if (stepped && !l.y.empty()) {  // hold the last value up to this sample
      l.x.push_back(t[i]);
      l.y.push_back(l.y.back());
    }
    l.x.push_back(t[i]);
    l.y.push_back(v[i]);
  }
  if (stepped && !l.x.empty() && t_end > l.x.back()) {
    l.x.push_back(t_end);
    l.y.push_back(l.y.back());
  }
  return l;
}

}  // namespace plc::hmi
