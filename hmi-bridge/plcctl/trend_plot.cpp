#include "trend_plot.hpp"

#include <plplot/plplot.h>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace plc::hmi {

std::string write_trend_csv(const Trend& tr, const std::string& file) {
  std::ofstream f(file);
  if (!f) return "cannot write '" + file + "'";
  f << "time_s";
  for (const auto& n : tr.names) f << "," << n;
  f << "\n";
  f.precision(12);
  for (std::size_t i = 0; i < tr.t.size(); ++i) {
    f << tr.t[i];
    for (const auto& v : tr.value) f << "," << v[i];
    f << "\n";
  }
  f.close();
  return f ? "" : "writing '" + file + "' failed";
}

std::string write_trend_png(const Trend& tr, const std::string& file, const std::string& title) {
  if (tr.t.size() < 2) return "fewer than 2 samples: nothing to draw";
  {
    std::ofstream probe(file);
    if (!probe) return "cannot write '" + file + "'";
  }
  double ymin = INFINITY, ymax = -INFINITY;
  for (const auto& v : tr.value)
    for (double y : v)
      if (std::isfinite(y)) {
        ymin = std::min(ymin, y);
        ymax = std::max(ymax, y);
      }
  if (!std::isfinite(ymin)) return "no numeric values to draw";
  if (ymax - ymin < 1e-12) {
    ymin -= 1;
    ymax += 1;
  }
  const double pad = (ymax - ymin) * 0.05;
  // PLplot's pngcairo driver (Debian plplot-driver-cairo); a private stream.
  PLINT stream = 0;
  plmkstrm(&stream);
  plsdev("pngcairo");
  plsfnam(file.c_str());
  plsetopt("geometry", "1000x600");
  plscol0(0, 255, 255, 255);  // background white
  plscol0(15, 0, 0, 0);       // axes and labels black
  plinit();
  plcol0(15);  // black on the white background
  plenv(tr.t.front(), tr.t.back(), ymin - pad, ymax + pad, 0, 0);
  pllab("PLC time (s)", "value", title.c_str());
  static const PLINT colours[] = {1, 9, 3, 8, 12, 13, 4, 10};
  const PLINT n = PLINT(tr.t.size());
  for (std::size_t k = 0; k < tr.value.size(); ++k) {
    plcol0(colours[k % 8]);
    plline(n, tr.t.data(), tr.value[k].data());
    // Legend text at the top left, one line per variable.
    plmtex("t", -1.5 - 1.2 * double(k), 0.02, 0.0, tr.names[k].c_str());
  }
  plend1();
  return "";
}

}  // namespace plc::hmi
