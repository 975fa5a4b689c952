#include "plc/sim/nord_iparams.hpp"

#include <cmath>
#include <string>

#include "plc/fb/safety/nord_error_codes.hpp"

namespace plc::sim {

namespace err = plc::safety::nord::err;

namespace {
// What a config may give: anything a 16-bit parameter word holds (signed or
// unsigned; with the parameter's decimals for the REAL ones). A value the
// word holds but the manual's range excludes reaches the device, which
// reports it as its fatal range error (check() below); one the word cannot
// hold is a config error.
constexpr std::int64_t kWordMin = -32768, kWordMax = 65535;
std::int64_t word(const io::ModelParams& p, const std::string& key, std::int64_t def) {
  return p.get_int(key, def, kWordMin, kWordMax);
}
// P811 has two decimals, P821/P822 one (spec §4.5).
double word_real(const io::ModelParams& p, const std::string& key, double def, double scale) {
  return p.get_double(key, def, double(kWordMin) / scale, double(kWordMax) / scale);
}
template <std::size_t N>
void read_ints(const io::ModelParams& p, const char* name, std::array<std::int64_t, N>& a) {
  for (std::size_t i = 0; i < N; ++i)
    a[i] = word(p, std::string(name) + "_" + std::to_string(i + 1), a[i]);
}
template <std::size_t N>
void read_doubles(const io::ModelParams& p, const char* name, std::array<double, N>& a) {
  for (std::size_t i = 0; i < N; ++i)
    a[i] = word_real(p, std::string(name) + "_" + std::to_string(i + 1), a[i], 10);
}
bool bit01(std::int64_t v) { return v == 0 || v == 1; }
}  // namespace

NordIParams NordIParams::from(const io::ModelParams& p) {
  NordIParams r;
  read_ints(p, "p800", r.p800);
  r.p801 = word(p, "p801", r.p801);
  read_ints(p, "p802", r.p802);
  r.p803_ms = word(p, "p803", r.p803_ms);
  r.p804 = word(p, "p804", r.p804);
  r.p805_ms = word(p, "p805", r.p805_ms);
  read_ints(p, "p806", r.p806);
  r.p810 = word(p, "p810", r.p810);
  r.p811 = word_real(p, "p811", r.p811, 100);
  r.p812 = word(p, "p812", r.p812);
  read_ints(p, "p820", r.p820);
  read_doubles(p, "p821", r.p821_s);
  read_doubles(p, "p822", r.p822_s);
  read_ints(p, "p823", r.p823);
  read_ints(p, "p824", r.p824);
  r.p840 = static_cast<std::uint32_t>(p.get_int("p840", 0, 0, 0xFFFFFFFF));
  return r;
}

int NordIParams::pulses() const {
  static constexpr int kTable[18] = {500,  512,   1000,  1024,  2000,  2048,  4096,  5000,  -500,
                                     -512, -1000, -1024, -2000, -2048, -4096, -5000, -8192, 8192};
  return (p812 >= 0 && p812 <= 17) ? kTable[p812] : 0;
}

std::uint16_t NordIParams::check() const {
  for (auto v : p802)
    if (!bit01(v)) return err::kP802Range;
  if (p804 < 0 || p804 > 8) return err::kP804Range;
  if (p805_ms < 2 || p805_ms > 100) return err::kP805Range;
  for (auto v : p800)
    if (!bit01(v)) return err::kP800Range;
  if (p803_ms < 0 || p803_ms > 30000) return err::kP803Range;
  if (!bit01(p801)) return err::kP801Range;
  if (!bit01(p810) || p811 < 0.01 || p811 > 100.0 || p812 < 0 || p812 > 17)
    return err::kEncoderParRange;
  static constexpr std::uint16_t kFn[5] = {err::kSls, err::kSsr, err::kSdiP, err::kSdiN, err::kSos};
  for (std::size_t i = 0; i < 5; ++i) {
    // (f) variant of 5756-5761: P820 invalid, or on with the encoder off.
    if (!bit01(p820[i]) || (p820[i] == 1 && p810 == 0)) return kFn[i];
  }
  for (double t : p821_s)
    if (t < 0.0 || t > 60.0) return err::kP821Range;
  for (double t : p822_s)
    if (t < 0.0 || t > 60.0) return err::kP822Range;
  for (auto v : p823)
    if (v < 0 || v > 9999) return err::kP823Range;
  if (p823[5] > p823[4]) return err::kP823Range;  // min SSR > max SSR
  for (auto v : p824)
    if (v < 0 || v > 9999) return err::kP824Range;
  if (p810 == 1) {
    // Limit frequency of the encoder input: P811 x P812 x P823 / 60 < 150000.
    for (auto v : p823)
      if (p811 * std::abs(pulses()) * static_cast<double>(v) / 60.0 >= 150000.0)
        return err::kLimitFrequency;
  }
  return 0;
}

}  // namespace plc::sim
