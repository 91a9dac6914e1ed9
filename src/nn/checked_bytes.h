#pragma once
// The checksum nsf adds to its archive files (the model file, the training checkpoint), without
// torch: the zip's own comment field holds "nsf-crc32 <8 hex digits>", the CRC-32 of every byte
// of the file before the comment-length field, so the file stays a valid zip that older nsf
// versions and Python read (docs/TRAINING.md). nn/checked_archive.h writes and loads torch's
// archives with it; the torch-free runtime reads a model file's run-time record
// (nn/model_record.h) with it.
#include <cstddef>
#include <string>

namespace nsf {

// Bytes of the comment a checksummed file ends in.
size_t checksum_comment_length();

// Appends the checksum comment to `bytes`, a whole zip whose end record has no comment. `what`
// and `path` name the file in the internal error raised otherwise.
void add_checksum(std::string& bytes, const std::string& what, const std::string& path);

// The whole file, its checksum verified. Throws nsf::Error naming `what` and `path` when it is not
// a regular file, cannot be read, or does not match its checksum. `checked` says whether it had
// one (a file written before nsf stored one is returned unverified).
std::string read_checked_file(const std::string& path, const std::string& what, bool& checked);

// The CRC-32 a checksummed archive carries ("1a2b3c4d"), read from its end without verifying it;
// "" for a file without one or one that cannot be read. Names the file's contents in a results
// row (docs/RESULTS.md), so that a rerun can tell whether it uses the same model.
std::string stored_checksum(const std::string& path);

}  // namespace nsf
