// Decoding LCM messages from the network without trusting them, for the
// bridge and plcctl alike.
//
// lcm-gen's decoders resize a vector to the element count as sent before
// they look at how many bytes follow: a negative count throws
// std::length_error, a large one allocates gigabytes. checked_decode first
// walks the encoding by the type's shape (every count within the bytes that
// follow, every string length at least 1 and inside the message, nothing
// left over), and only then lets the generated decoder run.
//
// subscribe_checked subscribes a handler that sees only what checked_decode
// accepted (lcm-cpp's typed subscriptions, which the bridge no longer uses,
// decoded unchecked).
#pragma once

#include <cstddef>
#include <exception>
#include <string>

#include "plc/hmi/transport.hpp"
#include "softplc_hmi/alarm_t.hpp"
#include "softplc_hmi/cell_description_t.hpp"
#include "softplc_hmi/command_t.hpp"
#include "softplc_hmi/diagnostics_t.hpp"
#include "softplc_hmi/reply_t.hpp"
#include "softplc_hmi/stats_t.hpp"
#include "softplc_hmi/trace_sample_t.hpp"
#include "softplc_hmi/values_t.hpp"

namespace plc::hmi {

// Larger messages are refused unread.
inline constexpr std::size_t kMaxMessageBytes = 1 << 22;

// The shape of an encoding after its 8-byte fingerprint: b byte/boolean,
// i int32, l int64, d double, s string, n int32 element count, (..) a struct,
// *X X repeated by the last count of the same struct, NX X repeated N
// times (16b, 32b). Whether data (fingerprint included) has exactly that shape with
// plausible counts. The shapes follow hmi-bridge/lcm/*.lcm (a test encodes
// each type and checks that its shape consumes it exactly).
bool plausible_encoding(const char* shape, const void* data, std::size_t size);

template <class T>
const char* shape_of();
// clang-format off
template <> inline const char* shape_of<softplc_hmi::command_t>() { return "lssn*s16bl32b"; }
template <> inline const char* shape_of<softplc_hmi::reply_t>() { return "lsbssn*(sssssb)16b32b"; }
template <> inline const char* shape_of<softplc_hmi::values_t>() { return "lslllsbn*(isb)"; }
template <> inline const char* shape_of<softplc_hmi::trace_sample_t>() { return "llsn*i*d"; }
template <> inline const char* shape_of<softplc_hmi::stats_t>() { return "ls16bn*(slllllls)lllllllln*s*l"; }
template <> inline const char* shape_of<softplc_hmi::cell_description_t>() { return "ls16blbbn*(ssssbbb)32b"; }
template <> inline const char* shape_of<softplc_hmi::diagnostics_t>() { return "lsn*(sssssiissl)n*(sssbssslll)"; }
template <> inline const char* shape_of<softplc_hmi::alarm_t>() { return "sssbssslll"; }
// clang-format on

// Decodes data as T only when its encoding is plausible. Never throws.
template <class T>
bool checked_decode(const void* data, std::size_t size, T& out) {
  if (size > kMaxMessageBytes || !plausible_encoding(shape_of<T>(), data, size)) return false;
  try {
    return out.decode(data, 0, int(size)) >= 0;
  } catch (const std::exception&) {  // defence in depth: std::bad_alloc
    return false;
  }
}

// Subscribes handler->on(const T&) to channel; messages that do not decode
// as T go to handler->on_malformed() when it has one, else nowhere.
// The handler must outlive the subscription (unsubscribe it first).
template <class T, class Handler>
Transport::Subscription* subscribe_checked(Transport& transport, const std::string& channel,
                                           Handler* handler) {
  return transport.subscribe(channel, [handler](const ReceiveBuffer& rb, const std::string&) {
    T m;
    if (checked_decode(rb.data, rb.data_size, m))
      handler->on(m);
    else if constexpr (requires { handler->on_malformed(); })
      handler->on_malformed();
  });
}

}  // namespace plc::hmi
