// The NORD i-parameters P800-P824 (spec nord-profisafe.md §4.5) as the
// simulated F-device holds them, read from the model's params and checked
// against the manual's ranges; an out-of-range value is the device's fatal
// configuration error (5748-5766), not a config-file error, so that tests
// can exercise those codes.
#pragma once

#include <array>
#include <cstdint>

#include "plc/io/model_params.hpp"
#include "plc/types.hpp"

namespace plc::sim {

struct NordIParams {
  std::array<std::int64_t, 2> p800{0, 0};  // [1] SI1/SI2, [2] SO1/SO2: 0 single, 1 dual
  std::int64_t p801 = 0;                   // 0 module passivation, 1 channel passivation
  // [1] SI1 [2] SI2 [3] SO1 [4] SO2 [5] SO3 [6] TAKT1 [7] TAKT2
  std::array<std::int64_t, 7> p802{0, 0, 0, 0, 0, 0, 0};
  std::int64_t p803_ms = 10;  // discrepancy time 0..30000
  std::int64_t p804 = 0;      // OSSD pulse code 0..8
  std::int64_t p805_ms = 2;   // filter 2..100
  std::array<std::int64_t, 2> p806{0, 0};
  std::int64_t p810 = 0;  // encoder evaluation
  double p811 = 1.0;      // ratio 0.01..100
  std::int64_t p812 = 5;  // resolution code 0..17
  // [1] SLS [2] SSR [3] SDI-P [4] SDI-N [5] SOS
  std::array<std::int64_t, 5> p820{0, 0, 0, 0, 0};
  // activation time [1..4] SLS-0..3 [5] SSR [6] SDI-P [7] SDI-N [8] SOS, s
  std::array<double, 8> p821_s{};
  // reaction time [1..4] SLS-0..3 [5] SSR [6] SDI-P [7] SDI-N [8] SSM, s
  std::array<double, 8> p822_s{};
  // [1..4] max SLS-0..3 [5] max SSR [6] min SSR [7] max SSM, rpm
  std::array<std::int64_t, 7> p823{0, 0, 0, 0, 0, 0, 0};
  std::array<std::int64_t, 3> p824{0, 0, 0};  // [1] SDI-P [2] SDI-N [3] SOS, increments
  std::uint32_t p840 = 0;                     // i-parameter CRC (stored)

  // Keys: p800_1, p801, p802_1..7, p803, p804, p805, p806_1..2, p810, p811,
  // p812, p820_1..5, p821_1..8, p822_1..8, p823_1..7, p824_1..3, p840.
  static NordIParams from(const io::ModelParams& p);

  // The first fatal code the manual gives for these values, 0 if valid.
  [[nodiscard]] std::uint16_t check() const;

  // Encoder pulses per revolution for P812 (negative = reversed counting).
  [[nodiscard]] int pulses() const;
};

}  // namespace plc::sim
