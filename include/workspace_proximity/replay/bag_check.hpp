#pragma once
/// The structure of a ROS bag (format 2.0) checked before rosbag reads it. rosbag's C++ reader
/// trusts the file: a damaged record length or index entry makes it read outside its buffers
/// (a crash, found by corrupting the demo bag at random), and a damaged time makes a replay span
/// years. This reads the file once, the way rosbag will (file header, connections and chunk
/// infos at the index position, each chunk and the index records after it), and checks that
/// every record lies inside the file or its chunk, every chunk decompresses to its stated size,
/// and every index entry points at a message record of its chunk with the same connection and
/// time, inside its chunk's time range. One chunk is held at a time.

#include <cstdint>
#include <string>

namespace workspace_proximity {

struct BagStructure {
  std::uint32_t connections = 0;
  std::uint32_t chunks = 0;
  std::uint64_t messages = 0;  ///< index entries (one per message)
};

/// Throws ReplayError (kBag) naming the problem and where it is (byte offset, chunk): no such
/// file, not a bag, not indexed (an interrupted recording), truncated, or damaged. Bags of the
/// old 1.2 format are left to rosbag (returns an empty structure).
BagStructure checkBagStructure(const std::string& path);

}  // namespace workspace_proximity
