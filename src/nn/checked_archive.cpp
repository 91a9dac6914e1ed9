#include "nn/checked_archive.h"

#include "core/error.h"
#include "io/atomic_file.h"
#include "nn/checked_bytes.h"
#include "nn/zip_entries.h"

namespace nsf {

void save_checked_archive(torch::serialize::OutputArchive& a, const std::string& path,
                          const std::string& what) {
  std::string bytes;
  try {
    a.save_to([&](const void* data, size_t n) {
      bytes.append(static_cast<const char*>(data), n);
      return n;
    });
  } catch (const c10::Error& e) {
    fail("cannot write ", what, " ", path, ": ", e.what_without_backtrace());
  }
  add_checksum(bytes, what, path);
  write_file_atomic(path, bytes);
}

bool load_checked_archive(torch::serialize::InputArchive& a, const std::string& path,
                          const std::string& what) {
  bool checked = false;
  const std::string bytes = read_checked_file(path, what, checked);
  check_zip_entries(bytes, checked ? checksum_comment_length() : 0, what, path);
  try {
    a.load_from(bytes.data(), bytes.size(), torch::Device(torch::kCPU));
  } catch (const c10::Error& e) {
    fail("cannot read ", what, " ", path, " (not an nsf ", what,
         ", or damaged): ", e.what_without_backtrace());
  } catch (const std::exception& e) {
    // torch's TorchScript reader throws its own types (ErrorReport) for a damaged archive whose
    // checksum was made to match: still a file nsf cannot read.
    const std::string why = e.what();
    fail("cannot read ", what, " ", path, " (not an nsf ", what, ", or damaged)",
         why.empty() ? "" : ": ", why.substr(0, why.find('\n')));
  }
  return checked;
}

}  // namespace nsf
