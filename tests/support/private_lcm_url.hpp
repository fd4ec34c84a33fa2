#pragma once
// A udpm LCM URL on a port no other process on this host is using, for tests and benchmarks.
// udpm traffic is host-wide, so a fixed port crosses with every other run of the same test on
// the machine (other build trees, other users). The port comes from the kernel's ephemeral
// allocation (bind to port 0), which never hands out a port a socket has bound, e.g. another
// LCM instance's.
#include <string>

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

namespace porter::test {

inline int free_udp_port() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) return 0;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_ANY);
  addr.sin_port = 0;
  socklen_t len = sizeof addr;
  int port = 0;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0) {
    port = ntohs(addr.sin_port);
  }
  ::close(fd);
  return port;
}

/// "udpm://239.255.76.67:PORT?ttl=0" on a free port (host-local: ttl 0).
inline std::string private_lcm_url() {
  return "udpm://239.255.76.67:" + std::to_string(free_udp_port()) + "?ttl=0";
}

}  // namespace porter::test
