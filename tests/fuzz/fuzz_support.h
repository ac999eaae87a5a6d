// What the fuzz targets share: a folder of their own to write an input into (the readers under
// test take files and folders, as users give them), a loopback UDP port to send one to (the
// live sources take datagrams), and rules that do nothing for a match a players' source reads.
#pragma once

#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>

#include "game/game.h"

namespace quantum::fuzz {

// Rules that do nothing: the match is only there for what the players' input reads of it.
struct NoRules final : game::Rules {
  void factors(std::span<const game::FateView>, game::Match&, std::span<double> out, game::FactorTerms&) override {
    std::fill(out.begin(), out.end(), 1.0);
  }
  void on_event(const game::GameEvent&, game::Match&) override {}
};

// This process's own scratch folder (fuzzers may run side by side), made once.
inline const std::filesystem::path& scratch() {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("quantum_fuzz_" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

inline void write_file(const std::filesystem::path& path, const uint8_t* data, size_t size) {
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

// A UDP port nobody else uses: the one the kernel picks for a socket bound to port 0.
inline int free_port() {
  const int s = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t n = sizeof a;
  ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
  ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &n);
  ::close(s);
  return ntohs(a.sin_port);
}

// One datagram to `port` on this machine; on loopback it is waiting there once this returns.
inline void send_datagram(int port, const void* data, size_t size) {
  static const int out = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(uint16_t(port));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::sendto(out, data, std::min<size_t>(size, 65000), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
}

}  // namespace quantum::fuzz
