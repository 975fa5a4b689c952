// JSON text for the browser HMI's messages (hmi-bridge/README.md "Web
// HMI"): the bridge's LCM messages as the page reads them. Writing only:
// the server parses no JSON (commands come as lines, command_body.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "softplc_hmi/alarm_t.hpp"
#include "softplc_hmi/cell_description_t.hpp"
#include "softplc_hmi/diagnostics_t.hpp"
#include "softplc_hmi/reply_t.hpp"
#include "softplc_hmi/stats_t.hpp"
#include "softplc_hmi/trace_sample_t.hpp"
#include "softplc_hmi/values_t.hpp"

namespace plc::hmi::web {

// `s` as a JSON string, quotes included; bytes that are not valid UTF-8
// become U+FFFD, controls \u00XX.
void append_string(std::string& out, std::string_view s);
// A finite number as JSON; NaN and infinities (a REAL can hold them) as null.
void append_number(std::string& out, double v);

std::string description_json(const softplc_hmi::cell_description_t& d, bool read_only,
                             const std::string& login);
std::string values_json(const softplc_hmi::values_t& v, const softplc_hmi::trace_sample_t& t);
std::string stats_json(const softplc_hmi::stats_t& s, const std::string& web_counters);
std::string diagnostics_json(const softplc_hmi::diagnostics_t& d);
// An alarm event as the page lists it: `id` numbers it for acknowledge.
std::string alarm_json(const softplc_hmi::alarm_t& a, std::int64_t id, bool acked);
std::string reply_json(const softplc_hmi::reply_t& r);

}  // namespace plc::hmi::web
