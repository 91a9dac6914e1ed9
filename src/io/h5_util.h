#pragma once
// RAII and error plumbing over the HDF5 C API, shared by the run writer and reader. Internal: only
// io/*.cpp include it, so hdf5.h (a large C header full of macros) stays out of public headers.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace nsf::h5 {

// HDF5 1.10 frees a file whose close fails (the disk is full, the file size limit is reached) but
// keeps its identifier, so the library's own exit handler closes it a second time and crashes
// (SIGSEGV in H5F__close_cb). h5_util therefore replaces that handler (H5dont_atexit) with one that
// shuts the library down only if no close has failed; after a failed close the process exits
// without it (nsf closes every handle itself, so there is nothing left to flush).
void note_failed_close();

// Owns one HDF5 identifier. The close function depends on the object kind (file, dataset, ...).
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer close) : id_(id), close_(close) {}
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), close_(o.close_) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, H5I_INVALID_HID);
      close_ = o.close_;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  // Returns false when HDF5 refuses the close; closing a file flushes it, and that can fail
  // (a full disk). The identifier is given up either way: it must not be closed twice.
  bool reset() {
    if (id_ < 0) return true;
    const herr_t status = close_(std::exchange(id_, H5I_INVALID_HID));
    if (status < 0) note_failed_close();
    return status >= 0;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer close_ = nullptr;
};

// HDF5 prints its error stack to stderr by default; nsf reports through nsf::Error instead. Scoped
// so that a host program which embeds libnsf keeps its own HDF5 error settings.
class QuietErrors {
 public:
  QuietErrors();
  ~QuietErrors();
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

// Throws nsf::Error "<file>: <what> (HDF5: <innermost HDF5 message>)" and clears the error stack.
[[noreturn]] void fail(const std::string& file, const std::string& what);

// Returns id, or fails naming the file and `what` when id is an HDF5 error value.
hid_t check(hid_t id, const std::string& file, const std::string& what);

// A new HDF5 file at `tmp`, to be renamed to `dest`, created exclusively (H5F_ACC_EXCL: never
// through a link planted there) after clear_stale_temp (core/exclusive_file.h).
hid_t create_exclusive(const std::string& tmp, const std::string& dest);
void check_status(herr_t status, const std::string& file, const std::string& what);

// Root-group attributes. Writing replaces an attribute of the same name.
void write_attribute(hid_t loc, const std::string& name, double value, const std::string& file);
void write_attribute(hid_t loc, const std::string& name, int64_t value, const std::string& file);
void write_attribute(hid_t loc, const std::string& name, const std::string& value,
                     const std::string& file);
bool has_attribute(hid_t loc, const std::string& name);
double read_attribute_double(hid_t loc, const std::string& name, const std::string& file);
int64_t read_attribute_int(hid_t loc, const std::string& name, const std::string& file);
// Reads both variable-length strings (what nsf writes) and fixed-length ones (what some other
// tools write), so a file touched up by h5py still loads.
std::string read_attribute_string(hid_t loc, const std::string& name, const std::string& file);

// Current extent of a dataset, or fails if it does not exist.
std::vector<hsize_t> dataset_shape(hid_t file_id, const std::string& name, const std::string& file);

}  // namespace nsf::h5
