#include "io/h5_util.h"

#include "core/exclusive_file.h"

#include <atomic>
#include <cstdlib>

#include "core/error.h"

namespace nsf::h5 {

namespace {

std::atomic<bool> g_close_failed{false};

void shut_down_library() {
  if (!g_close_failed) H5close();
}

// Runs before main, hence before HDF5 initialises (H5dont_atexit only works then).
const bool g_exit_handler_installed = [] {
  H5dont_atexit();
  return std::atexit(shut_down_library) == 0;
}();

}  // namespace

void note_failed_close() {
  g_close_failed = true;
}

QuietErrors::QuietErrors() {
  H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

QuietErrors::~QuietErrors() {
  H5Eset_auto2(H5E_DEFAULT, func_, data_);
}

namespace {

// The innermost entry is the one that says what actually went wrong ("truncated file: eof = ...",
// "file signature not found"); the outer ones only repeat "unable to open file".
herr_t keep_innermost(unsigned n, const H5E_error2_t* err, void* out) {
  if (n == 0 && err->desc != nullptr) *static_cast<std::string*>(out) = err->desc;
  return 0;
}

std::string take_hdf5_message() {
  std::string msg;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, keep_innermost, &msg);
  H5Eclear2(H5E_DEFAULT);
  return msg;
}

Handle open_root_attribute(hid_t loc, const std::string& name, const std::string& file) {
  if (!has_attribute(loc, name)) fail(file, "missing attribute '" + name + "'");
  return Handle(check(H5Aopen(loc, name.c_str(), H5P_DEFAULT), file, "opening attribute " + name),
                H5Aclose);
}

void write_scalar(hid_t loc, const std::string& name, hid_t file_type, hid_t mem_type,
                  const void* value, const std::string& file) {
  if (has_attribute(loc, name)) {
    check_status(H5Adelete(loc, name.c_str()), file, "replacing attribute " + name);
  }
  Handle space(check(H5Screate(H5S_SCALAR), file, "attribute space"), H5Sclose);
  Handle attr(check(H5Acreate2(loc, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                    file, "creating attribute " + name),
              H5Aclose);
  check_status(H5Awrite(attr.get(), mem_type, value), file, "writing attribute " + name);
}

}  // namespace

void fail(const std::string& file, const std::string& what) {
  const std::string detail = take_hdf5_message();
  if (detail.empty()) nsf::fail(file, ": ", what);
  nsf::fail(file, ": ", what, " (HDF5: ", detail, ")");
}

hid_t check(hid_t id, const std::string& file, const std::string& what) {
  if (id < 0) fail(file, what);
  return id;
}

void check_status(herr_t status, const std::string& file, const std::string& what) {
  if (status < 0) fail(file, what);
}

void write_attribute(hid_t loc, const std::string& name, double value, const std::string& file) {
  write_scalar(loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value, file);
}

void write_attribute(hid_t loc, const std::string& name, int64_t value, const std::string& file) {
  write_scalar(loc, name, H5T_STD_I64LE, H5T_NATIVE_INT64, &value, file);
}

void write_attribute(hid_t loc, const std::string& name, const std::string& value,
                     const std::string& file) {
  // Variable-length UTF-8: h5py returns it as str, and there is no 64 KiB header limit to hit
  // with a long scene JSON (the text lives in the global heap).
  Handle type(check(H5Tcopy(H5T_C_S1), file, "string type"), H5Tclose);
  check_status(H5Tset_size(type.get(), H5T_VARIABLE), file, "string type");
  check_status(H5Tset_cset(type.get(), H5T_CSET_UTF8), file, "string type");
  const char* text = value.c_str();
  write_scalar(loc, name, type.get(), type.get(), &text, file);
}

bool has_attribute(hid_t loc, const std::string& name) {
  return H5Aexists(loc, name.c_str()) > 0;
}

double read_attribute_double(hid_t loc, const std::string& name, const std::string& file) {
  Handle attr = open_root_attribute(loc, name, file);
  Handle type(check(H5Aget_type(attr.get()), file, "attribute " + name), H5Tclose);
  const H5T_class_t cls = H5Tget_class(type.get());
  if (cls != H5T_FLOAT && cls != H5T_INTEGER) fail(file, "attribute '" + name + "' is not numeric");
  double v = 0;
  check_status(H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &v), file, "reading attribute " + name);
  return v;
}

int64_t read_attribute_int(hid_t loc, const std::string& name, const std::string& file) {
  Handle attr = open_root_attribute(loc, name, file);
  Handle type(check(H5Aget_type(attr.get()), file, "attribute " + name), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_INTEGER) {
    fail(file, "attribute '" + name + "' is not an integer");
  }
  int64_t v = 0;
  check_status(H5Aread(attr.get(), H5T_NATIVE_INT64, &v), file, "reading attribute " + name);
  return v;
}

std::string read_attribute_string(hid_t loc, const std::string& name, const std::string& file) {
  Handle attr = open_root_attribute(loc, name, file);
  Handle type(check(H5Aget_type(attr.get()), file, "attribute " + name), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_STRING) fail(file, "attribute '" + name + "' is not text");
  const htri_t variable = H5Tis_variable_str(type.get());
  check_status(variable, file, "attribute " + name);
  if (variable > 0) {
    char* text = nullptr;
    check_status(H5Aread(attr.get(), type.get(), &text), file, "reading attribute " + name);
    std::string out = text != nullptr ? text : "";
    H5free_memory(text);
    return out;
  }
  std::string out(H5Tget_size(type.get()), '\0');
  check_status(H5Aread(attr.get(), type.get(), out.data()), file, "reading attribute " + name);
  out.resize(out.find_last_not_of('\0') + 1);  // fixed-length strings are NUL padded
  return out;
}

std::vector<hsize_t> dataset_shape(hid_t file_id, const std::string& name,
                                   const std::string& file) {
  if (H5Lexists(file_id, name.c_str(), H5P_DEFAULT) <= 0) fail(file, "missing dataset " + name);
  Handle set(check(H5Dopen2(file_id, name.c_str(), H5P_DEFAULT), file, "opening dataset " + name),
             H5Dclose);
  Handle space(check(H5Dget_space(set.get()), file, "dataset " + name), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) fail(file, "dataset " + name + " has an unreadable shape");
  std::vector<hsize_t> dims(static_cast<size_t>(rank));
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  return dims;
}

hid_t create_exclusive(const std::string& tmp, const std::string& dest) {
  clear_stale_temp(tmp, dest);
  return check(H5Fcreate(tmp.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT), tmp,
               "cannot create file");
}

}  // namespace nsf::h5
