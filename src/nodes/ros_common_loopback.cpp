// Loopback-only sockets for the nodes. roscpp binds its TCPROS listener to 127.0.0.1 when ROS_IP is 127.* or
// ROS_HOSTNAME/ROS_IP is localhost, but its XML-RPC server (xmlrpcpp's XmlRpcSocket::bind) always binds every
// interface, where anyone on the network could call `shutdown`. This bind() stands in for libc's in the nodes
// (the executable's symbol comes first for the ROS libraries) and, in that same loopback mode, turns a wildcard
// address into the loopback one. A multi-host run (ROS_IP set to a real address) binds as roscpp asks.
#include <dlfcn.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <cstdlib>
#include <cstring>

namespace {

bool loopback_only() {
  static const bool on = [] {
    const char* ip = std::getenv("ROS_IP");
    const char* host = std::getenv("ROS_HOSTNAME");
    return (host && !std::strcmp(host, "localhost")) || (ip && (!std::strcmp(ip, "localhost") || !std::strncmp(ip, "127.", 4)));
  }();
  return on;
}

}  // namespace

extern "C" int bind(int fd, const struct sockaddr* addr, socklen_t len) __THROW {
  using BindFn = int (*)(int, const struct sockaddr*, socklen_t);
  static const auto real = reinterpret_cast<BindFn>(dlsym(RTLD_NEXT, "bind"));
  if (loopback_only() && addr && addr->sa_family == AF_INET && len >= sizeof(sockaddr_in)) {
    sockaddr_in a;
    std::memcpy(&a, addr, sizeof a);
    if (a.sin_addr.s_addr == htonl(INADDR_ANY)) {
      a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      return real(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a);
    }
  } else if (loopback_only() && addr && addr->sa_family == AF_INET6 && len >= sizeof(sockaddr_in6)) {
    sockaddr_in6 a;
    std::memcpy(&a, addr, sizeof a);
    if (!std::memcmp(&a.sin6_addr, &in6addr_any, sizeof a.sin6_addr)) {
      a.sin6_addr = in6addr_loopback;
      return real(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a);
    }
  }
  return real(fd, addr, len);
}
