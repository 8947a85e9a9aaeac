// The record structure of a ROS 1 bag (format 2.0), checked before rosbag_storage reads it.
//
// rosbag_storage (Debian's librosbag-storage) trusts the lengths a bag states: a damaged header field or record
// length makes it read past its buffers (found by fuzzing, tests/fuzz/regressions/rosbag). This walks the bag's
// records with every length bounded by what holds it, so a damaged bag is refused with the byte offset named:
//   file      "#ROSBAG V2.0\n", then records: uint32 header_len, header, uint32 data_len, data
//   header    fields: uint32 field_len, "name=value" (field_len bytes, '=' within)
//   op 0x03   the bag header: index_pos must be a record's start (or 0, an unindexed bag)
//   op 0x05   a chunk: with compression none, its data is again records (walked the same way), of its stated size
//   op 0x04   index data, after its chunk: count entries of (time, uint32 offset); each offset a record's start in
//             that chunk (uncompressed chunks)
//   op 0x06   chunk info: chunk_pos must be a chunk's start
//   op 0x07   a connection: its data is a header too
// Compressed chunks (bz2, lz4) are left to rosbag_storage: their records and the offsets into them are
// checked only after decompression, which is the library's.
#pragma once

#include <string>

namespace gyrosid {

// Error naming `path` and the byte offset of the first fault.
void check_rosbag_structure(const std::string& path);

}  // namespace gyrosid
