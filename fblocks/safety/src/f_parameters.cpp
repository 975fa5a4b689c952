#include "plc/fb/safety/f_parameters.hpp"

#include "plc/fb/safety/crc.hpp"
#include "plc/io/byte_order.hpp"

namespace plc::safety {

std::uint16_t compute_crc1(std::span<const std::uint8_t, kFParamBlockSize> block) {
  return crc1(block.first(12));
}

void encode(FParameters& p, std::span<std::uint8_t, kFParamBlockSize> out, bool fill_crc1) {
  out[0] = static_cast<std::uint8_t>((p.check_seq_nr ? 0x01 : 0) | (p.check_ipar ? 0x02 : 0) |
                                     ((p.sil & 0x3) << 2) | ((p.crc_length & 0x3) << 4));
  out[1] = static_cast<std::uint8_t>(((p.block_id & 0x7) << 3) | ((p.par_version & 0x3) << 6));
  std::span<std::uint8_t> s(out.data(), out.size());
  io::store_be<std::uint16_t>(s, 2, p.source_add);
  io::store_be<std::uint16_t>(s, 4, p.dest_add);
  io::store_be<std::uint16_t>(s, 6, p.wd_time_ms);
  io::store_be<std::uint32_t>(s, 8, p.ipar_crc);
  if (fill_crc1) p.par_crc = compute_crc1(out);
  io::store_be<std::uint16_t>(s, 12, p.par_crc);
}

FParameters decode(std::span<const std::uint8_t, kFParamBlockSize> in) {
  FParameters p;
  p.check_seq_nr = in[0] & 0x01;
  p.check_ipar = in[0] & 0x02;
  p.sil = (in[0] >> 2) & 0x3;
  p.crc_length = (in[0] >> 4) & 0x3;
  p.block_id = (in[1] >> 3) & 0x7;
  p.par_version = (in[1] >> 6) & 0x3;
  std::span<const std::uint8_t> s(in.data(), in.size());
  p.source_add = io::load_be<std::uint16_t>(s, 2);
  p.dest_add = io::load_be<std::uint16_t>(s, 4);
  p.wd_time_ms = io::load_be<std::uint16_t>(s, 6);
  p.ipar_crc = io::load_be<std::uint32_t>(s, 8);
  p.par_crc = io::load_be<std::uint16_t>(s, 12);
  return p;
}

}  // namespace plc::safety
