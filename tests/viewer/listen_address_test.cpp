// --bind's address parser: literals only, in their canonical form; the URL and civetweb's
// listening_ports entry, IPv6 in brackets.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "app/viewer/listen_address.h"
#include "core/error.h"

namespace multiray::app::viewer {
namespace listen_address_test {

TEST(ListenAddress, Ipv4LiteralsAndLocalhost) {
  ListenAddress a = parse_listen_address("127.0.0.1", false);
  EXPECT_EQ(a.host, "127.0.0.1");
  EXPECT_TRUE(a.loopback);
  EXPECT_FALSE(a.ipv6);
  EXPECT_EQ(a.listening_port(8080), "127.0.0.1:8080");
  EXPECT_EQ(a.url(8080), "http://127.0.0.1:8080/");
  EXPECT_TRUE(parse_listen_address("127.1.2.3", false).loopback);
  EXPECT_EQ(parse_listen_address("localhost", false).host, "127.0.0.1");
  a = parse_listen_address("0.0.0.0", false);
  EXPECT_FALSE(a.loopback);
  EXPECT_EQ(parse_listen_address("192.168.1.20", false).host, "192.168.1.20");
}

TEST(ListenAddress, Ipv6LiteralsNeedIpv6) {
  const ListenAddress a = parse_listen_address("::1", true);
  EXPECT_TRUE(a.ipv6);
  EXPECT_TRUE(a.loopback);
  EXPECT_EQ(a.listening_port(0), "[::1]:0");
  EXPECT_EQ(a.url(8080), "http://[::1]:8080/");
  EXPECT_EQ(parse_listen_address("0:0:0:0:0:0:0:1", true).host, "::1");
  EXPECT_FALSE(parse_listen_address("::", true).loopback);
  try {
    parse_listen_address("::1", false);
    ADD_FAILURE() << "::1 accepted without IPv6";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("IPv6"), std::string::npos) << e.what();
  }
}

// Before, civetweb's own parser read 256.0.0.0 as 0.0.0.0 (each part taken modulo 256).
TEST(ListenAddress, AnythingElseIsRefusedInOneLine) {
  for (const std::string& bad : std::vector<std::string>{
           "256.0.0.0", "1.2.3", "1.2.3.4.5", "01.2.3.4", "1.2.3.-4", "127.0.0.1:80", "[::1]",
           "fe80::1%lo", "::1::2", "example.com", "LOCALHOST", "", " 127.0.0.1", "127.0.0.1 ",
           std::string("127.0.0.1\0x", 11), "1.2.3.4\n5", std::string(300, '1')}) {
    try {
      parse_listen_address(bad, true);
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("--bind"), std::string::npos) << e.what();
    }
  }
}

}  // namespace listen_address_test
}  // namespace multiray::app::viewer
