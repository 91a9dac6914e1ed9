#pragma once
// Archive files (the model file, the training checkpoint) that carry a CRC-32 of their bytes, so
// that a damaged or tampered file is refused on load instead of giving silently wrong fields.
// The archive is a zip (torch's format); the checksum lives in the zip's own comment field,
// "nsf-crc32 <8 hex digits>", over every byte of the file before the comment-length field, so
// the file stays a valid zip that older nsf versions and Python read (docs/TRAINING.md).
#include <torch/serialize/archive.h>

#include <string>

#include "nn/checked_bytes.h"  // stored_checksum

namespace nsf {

// Writes `a` to `path` atomically (tmp + rename), checksum included. `what` names the file in
// messages ("model", "checkpoint").
void save_checked_archive(torch::serialize::OutputArchive& a, const std::string& path,
                          const std::string& what);

// Loads `path` into `a`, verifying the checksum; throws nsf::Error naming the file when it does
// not match or the file is not an archive. Returns false for a file written before nsf stored a
// checksum (loaded unverified).
bool load_checked_archive(torch::serialize::InputArchive& a, const std::string& path,
                          const std::string& what);

}  // namespace nsf
