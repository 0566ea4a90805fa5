// The address `multiray view --bind` listens on, parsed strictly: an IPv4 or IPv6 literal
// (inet_pton), or "localhost" for 127.0.0.1. Pure: no socket, no civetweb.
#pragma once

#include <string>

namespace multiray::app::viewer {

struct ListenAddress {
  std::string host;  // canonical literal (inet_ntop): "127.0.0.1", "::1"
  bool ipv6 = false;
  bool loopback = false;  // 127.0.0.0/8 or ::1: only this machine can connect

  // civetweb's listening_ports entry: "127.0.0.1:8080", "[::1]:8080".
  std::string listening_port(int port) const;
  // The page's address for a browser: "http://127.0.0.1:8080/", "http://[::1]:8080/".
  std::string url(int port) const;
};

// Throws InputError (one line naming `text`) for anything but an IPv4 literal in dotted
// decimal (each part 0..255, no leading zeros), an IPv6 literal without a zone, or
// "localhost"; and for an IPv6 literal when `ipv6_available` is false (the server library
// was built without IPv6).
ListenAddress parse_listen_address(const std::string& text, bool ipv6_available);

}  // namespace multiray::app::viewer
