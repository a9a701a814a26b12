#pragma once
/// The 64-bit finaliser of MurmurHash3 (fmix64), shared by the open-addressing tables.
/// Proxy ids and body serials are small consecutive integers, so pair keys need mixing
/// before masking or linear probe sequences cluster.

#include <cstdint>

namespace workspace_proximity {

inline std::uint64_t mixKey(std::uint64_t k) {
  k ^= k >> 33;
  k *= 0xff51afd7ed558ccdULL;
  k ^= k >> 33;
  k *= 0xc4ceb9fe1a85ec53ULL;
  k ^= k >> 33;
  return k;
}

}  // namespace workspace_proximity
