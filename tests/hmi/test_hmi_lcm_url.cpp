// The LCM url, parsed by us (lcm_url.hpp): liblcm 1.3.1's syntax (lcm.c
// lcm_parse_url; lcm_udpm.c parse_mc_addr_and_port, new_argument) with an
// error for everything liblcm only warns about or gets wrong.
#include <gtest/gtest.h>

#include "plc/hmi/lcm_url.hpp"
#include "plc/hmi/transport.hpp"

using namespace plc::hmi;

namespace {

std::string error_of(const std::string& url) {
  std::string err;
  EXPECT_FALSE(parse_lcm_url(url, err)) << url;
  return err;
}

}  // namespace

TEST(HmiLcmUrl, UdpmAddressPortAndOptions) {
  std::string err;
  auto u = parse_lcm_url("udpm://239.255.76.67:7667?ttl=0", err);
  ASSERT_TRUE(u) << err;
  EXPECT_EQ(u->kind, LcmUrl::Kind::Udpm);
  EXPECT_EQ(u->group, 0xEFFF4C43U);
  EXPECT_EQ(u->port, 7667);
  EXPECT_EQ(u->ttl, 0);
  EXPECT_EQ(u->recv_buf_size, 0);
  u = parse_lcm_url("udpm://224.1.2.3:1?recv_buf_size=4194304&ttl=1", err);
  ASSERT_TRUE(u) << err;
  EXPECT_EQ(u->group, 0xE0010203U);
  EXPECT_EQ(u->port, 1);
  EXPECT_EQ(u->ttl, 1);
  EXPECT_EQ(u->recv_buf_size, 4194304);
  // liblcm's default when the address is left out (parse_mc_addr_and_port).
  u = parse_lcm_url("udpm://?ttl=255", err);
  ASSERT_TRUE(u) << err;
  EXPECT_EQ(u->group, 0xEFFF4C43U);
  EXPECT_EQ(u->port, 7667);
  EXPECT_EQ(u->ttl, 255);
  u = parse_lcm_url("memq://", err);
  ASSERT_TRUE(u) << err;
  EXPECT_EQ(u->kind, LcmUrl::Kind::Memq);
}

TEST(HmiLcmUrl, ErrorsSayWhatIsWrong) {
  EXPECT_NE(error_of("239.255.76.67:7667").find("not an LCM url"), std::string::npos);
  EXPECT_NE(error_of("tcpq://localhost:7700").find("liblcm's own parser"), std::string::npos);
  EXPECT_NE(error_of("udpm://239.255.76.67").find("has no port"), std::string::npos);
  EXPECT_NE(error_of("udpm://239.255.76:7667").find("not an IPv4 address"), std::string::npos);
  EXPECT_NE(error_of("udpm://10.0.0.1:7667").find("not a multicast address"), std::string::npos);
  EXPECT_NE(error_of("udpm://239.255.76.67:0").find("port '0'"), std::string::npos);
  EXPECT_NE(error_of("udpm://239.255.76.67:65536").find("1 to 65535"), std::string::npos);
  EXPECT_NE(error_of("udpm://239.255.76.67:0x1e33").find("port"), std::string::npos);
  // liblcm stores ttl in a uint8_t: 256 would be 0, this host only.
  EXPECT_NE(error_of("udpm://239.255.76.67:7667?ttl=256").find("0 to 255"), std::string::npos);
  EXPECT_NE(error_of("udpm://239.255.76.67:7667?ttl=").find("ttl ''"), std::string::npos);
  EXPECT_NE(error_of("udpm://239.255.76.67:7667?ttl=-1").find("ttl"), std::string::npos);
  EXPECT_NE(error_of("udpm://239.255.76.67:7667?recv_buf_size=big").find("recv_buf_size"),
            std::string::npos);
  EXPECT_NE(error_of("udpm://239.255.76.67:7667?ttl=0&ttl=1").find("given twice"),
            std::string::npos);
  EXPECT_NE(error_of("udpm://239.255.76.67:7667?transmit_only=true").find("not known"),
            std::string::npos);
  EXPECT_NE(error_of("memq://x").find("memq:// takes no address"), std::string::npos);
}

// open_transport passes the url's error on; memq:// always opens.
TEST(HmiLcmUrl, OpenTransportReportsTheUrlsError) {
  std::string err;
  EXPECT_FALSE(open_transport("udpm://1.2.3.4:7667", err));
  EXPECT_NE(err.find("not a multicast address"), std::string::npos) << err;
  EXPECT_TRUE(open_transport("memq://", err));
}
