#include "plc/hmi/udpm_wire.hpp"

#include <limits>

namespace plc::hmi::udpm {

std::size_t datagram_count(std::string_view channel, std::size_t payload_size) {
  // msg_size is a u32; a channel longer than 63 is refused (lcm_udpm.c:611).
  if (channel.size() > kMaxChannelLength ||
      payload_size > std::numeric_limits<std::uint32_t>::max())
    return 0;
  const std::size_t total = channel.size() + 1 + payload_size;
  if (total <= kShortMessageMaxSize) return 1;
  const std::size_t n = (total + kFragmentMaxPayload - 1) / kFragmentMaxPayload;
  return n > kMaxFragments ? 0 : n;
}

}  // namespace plc::hmi::udpm
