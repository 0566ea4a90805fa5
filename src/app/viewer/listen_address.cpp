#include "app/viewer/listen_address.h"

#include <arpa/inet.h>

#include <cstring>

#include "core/error.h"

namespace multiray::app::viewer {

namespace {
// `text` cut to 64 bytes with control characters as '?', so the error stays one line.
std::string shown(const std::string& text) {
  std::string s = text.substr(0, 64);
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return s;
}
}  // namespace

std::string ListenAddress::listening_port(int port) const {
  return (ipv6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
}

std::string ListenAddress::url(int port) const { return "http://" + listening_port(port) + "/"; }

ListenAddress parse_listen_address(const std::string& text, bool ipv6_available) {
  ListenAddress a;
  const std::string literal = text == "localhost" ? "127.0.0.1" : text;
  char canonical[INET6_ADDRSTRLEN] = "";
  in_addr v4{};
  in6_addr v6{};
  // inet_pton takes a C string: an embedded NUL would cut the text short.
  const bool clean = literal.find('\0') == std::string::npos;
  if (clean && inet_pton(AF_INET, literal.c_str(), &v4) == 1) {
    inet_ntop(AF_INET, &v4, canonical, sizeof canonical);
    a.loopback = (ntohl(v4.s_addr) >> 24) == 127;
  } else if (clean && inet_pton(AF_INET6, literal.c_str(), &v6) == 1) {
    if (!ipv6_available)
      throw InputError("--bind " + text +
                       ": this build's civetweb has no IPv6 support; use an IPv4 address "
                       "such as 127.0.0.1");
    inet_ntop(AF_INET6, &v6, canonical, sizeof canonical);
    a.ipv6 = true;
    a.loopback = IN6_IS_ADDR_LOOPBACK(&v6);
  } else {
    throw InputError("--bind '" + shown(text) +
                     "' is not an IP address (IPv4 like 127.0.0.1 or 0.0.0.0, IPv6 like ::1, "
                     "or localhost)");
  }
  a.host = canonical;
  return a;
}

}  // namespace multiray::app::viewer
