// The socket of one of civetweb's connections, found from the addresses civetweb reports for
// it: civetweb's public API gives no descriptor, and the viewer reads its WebSockets itself
// (ws_frames.h says why).
#pragma once

namespace multiray::app::viewer {

// The descriptor of this process's TCP socket whose local port is `server_port` and whose peer
// is `remote_addr` (as inet_ntop writes it) port `remote_port`; -1 when there is none. That
// 4-tuple names one open connection, so the answer is the connection's own socket (a client
// socket of this process to the server has the ports the other way round). Linux: lists
// /proc/self/fd.
int find_connection_socket(int server_port, const char* remote_addr, int remote_port);

}  // namespace multiray::app::viewer
