// How `plcctl trend` lays out its PNG: which variables share a panel, the
// panel's y range, and how each variable's line is drawn. Kept apart from
// the drawing (trend_plot.cpp, PLplot) so that these decisions can be tested
// without reading pixels.
//
// The cell description (var_desc_t) gives each variable its IEC type and no
// engineering unit, so the panels go by type class, stacked over one time
// axis: BOOL, integers (SINT..ULINT, BYTE..LWORD), REAL/LREAL, TIME (in
// seconds). Values of one class share a scale more often than values of
// different classes do (a level in counts is not a flow in l/s, but a BOOL
// is never either). A BOOL and an integer hold their value until the next
// sample, so they are drawn as steps; REAL and TIME as straight lines
// between samples. BOOLs get a lane each (as a logic analyser draws them):
// several on one 0/1 axis would hide each other.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "trend_plot.hpp"

namespace plc::hmi {

enum class TrendClass { Bool, Integer, Real, Time };

// The class of an IEC type name as var_desc_t gives it; nullopt for a type
// that has no numeric value to draw (STRING).
std::optional<TrendClass> trend_class(std::string_view iec_type);

struct TrendPanel {
  TrendClass cls = TrendClass::Real;
  std::string y_label;              // "BOOL", "integer", "REAL", "TIME (s)"
  bool stepped = false;             // sample and hold: BOOL and integers
  std::vector<std::size_t> series;  // indices into Trend::names, in trend order
  std::vector<double> offset;       // per series: added to its values (BOOL lanes)
  double ymin = 0, ymax = 1;        // the panel's y range, padded
};

// The panels, top to bottom in the order BOOL, integer, REAL, TIME; a class
// none of the trend's variables has gets no panel, nor does a variable
// whose type cannot be drawn. Y ranges come from the finite samples: 5 %
// padding, a flat series +-1 around its value; the BOOL panel holds its
// lanes (lane k of n at offset 1.5 x (n-1-k): the first variable on top;
// the range -0.25 .. 1.5 x n leaves room for each lane's name above it).
std::vector<TrendPanel> trend_panels(const Trend& tr);

struct TrendLine {
  std::vector<double> x, y;
};

// One variable's line: its finite samples (a sample of another task's
// snapshot has NaN here: left out). Stepped: each value is held until the
// next sample's time, where the line rises or falls vertically, and the
// last one until `t_end` (the trend's last sample).
TrendLine trend_line(const std::vector<double>& t, const std::vector<double>& v, bool stepped,
                     double t_end);

}  // namespace plc::hmi
