#include "trend_plot.hpp"

#include <plplot/plplot.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "trend_layout.hpp"

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
  bool any = false;
  for (const auto& v : tr.value)
    for (double y : v) any = any || std::isfinite(y);
  const std::vector<TrendPanel> panels = trend_panels(tr);
  if (!any || panels.empty()) return "no numeric values to draw";
  {
    std::ofstream probe(file);
    if (!probe) return "cannot write '" + file + "'";
  }
  const double t0 = tr.t.front(), t1 = tr.t.back();
  const std::size_t n = panels.size();
  const std::string geometry = "1000x" + std::to_string(std::max<std::size_t>(600, 150 + 250 * n));
  // PLplot's pngcairo driver (Debian plplot-driver-cairo); a private stream.
  PLINT stream = 0;
  plmkstrm(&stream);
  plsdev("pngcairo");
  plsfnam(file.c_str());
  plsetopt("geometry", geometry.c_str());
  plscol0(0, 255, 255, 255);  // background white
  plscol0(15, 0, 0, 0);       // axes and labels black
  plscol0(7, 215, 215, 215);  // grid light grey
  // The series: dark enough to read on white, told apart by hue.
  static const PLINT colours[] = {1, 2, 3, 4, 5, 6, 8, 9};
  static const unsigned char rgb[][3] = {{31, 119, 180},  {214, 39, 40},  {44, 160, 44},
                                         {148, 103, 189}, {255, 127, 14}, {140, 86, 75},
                                         {23, 190, 207},  {127, 127, 127}};
  for (std::size_t c = 0; c < 8; ++c) plscol0(colours[c], rgb[c][0], rgb[c][1], rgb[c][2]);
  plinit();
  pladv(0);
  plschr(0, 0.85);
  // Panels top to bottom between these page fractions, a small gap apart.
  const double top = 0.93, bottom = 0.09, gap = 0.025;
  const double h = (top - bottom - gap * double(n - 1)) / double(n);
  std::size_t colour = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const TrendPanel& p = panels[i];
    const double y1 = top - double(i) * (h + gap);
    plvpor(0.13, 0.97, y1 - h, y1);
    plwind(t0, t1, p.ymin, p.ymax);
    const bool last = i + 1 == n;
    const bool lanes = p.cls == TrendClass::Bool;
    // BOOL lanes have no numeric axis (a lane's name says what it is).
    plcol0(7);
    plbox("g", 0, 0, lanes ? "" : "g", 0, 0);
    plcol0(15);
    plbox(last ? "bcnst" : "bcst", 0, 0, lanes ? "bc" : "bcnstv", 0, 0);
    plmtex("l", lanes ? 1.5 : 5.5, 0.5, 0.5, p.y_label.c_str());
    if (i == 0) plmtex("t", 1.0, 0.5, 0.5, title.c_str());
    if (last) plmtex("b", 3.0, 0.5, 0.5, "PLC time (s)");
    for (std::size_t j = 0; j < p.series.size(); ++j) {
      const std::size_t k = p.series[j];
      TrendLine l = trend_line(tr.t, tr.value[k], p.stepped, t1);
      for (double& y : l.y) y += p.offset[j];
      plcol0(colours[colour++ % 8]);
      plwidth(2.0);
      if (l.x.size() >= 2) plline(PLINT(l.x.size()), l.x.data(), l.y.data());
      plwidth(1.0);
      if (lanes)  // the name just above its lane's high level
        plptex(t0 + (t1 - t0) * 0.01, p.offset[j] + 1.1, 1, 0, 0, tr.names[k].c_str());
      else  // a legend line per variable at the panel's top left
        plmtex("t", -1.5 - 1.2 * double(j), 0.02, 0.0, tr.names[k].c_str());
    }
  }
  plend1();
  return "";
}

}  // namespace plc::hmi
