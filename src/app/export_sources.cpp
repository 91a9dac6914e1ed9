#include "app/export_sources.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <system_error>

#include "core/error.h"
#include "core/exclusive_file.h"
#include "core/path_clash.h"
#include "io/atomic_file.h"

namespace nsf::app {

namespace {

namespace fs = std::filesystem;

// name_NNNN.ply / .vtk / .vtu: digits only between the name and the extension, so that the frames
// of a run named "a" are not mistaken for those of "a_1".
bool is_frame_file(const std::string& file, const std::string& name) {
  if (file.rfind(name + "_", 0) != 0) return false;
  const size_t digits = name.size() + 1, dot = file.find('.', digits);
  if (dot == std::string::npos || dot == digits) return false;
  for (size_t i = digits; i < dot; ++i)
    if (!std::isdigit(static_cast<unsigned char>(file[i]))) return false;
  const std::string ext = file.substr(dot);
  return ext == ".ply" || ext == ".vtk" || ext == ".vtu";
}

bool is_collection_file(const std::string& file, const std::string& name) {
  for (const char* ext : {".pvd", ".vtk.series", ".series.xdmf", ".series.h5"})
    if (file == name + ext) return true;
  return false;
}

std::string absolute(const std::string& path) {
  std::error_code ec;
  const fs::path p = fs::absolute(path, ec);
  return ec ? path : p.lexically_normal().string();
}

}  // namespace

std::vector<std::string> exported_files(const std::string& dir, const std::string& name) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string file = e.path().filename().string();
    if (is_frame_file(file, name) || is_collection_file(file, name)) out.push_back(file);
  }
  std::sort(out.begin(), out.end());
  return out;
}

ExportSources::ExportSources(std::string dir) : dir_(std::move(dir)) {
  const fs::path record = fs::path(dir_) / kExportSourcesFile;
  std::error_code ec;
  if (!fs::is_regular_file(record, ec)) return;
  // A record that does not parse records nothing: files it would have vouched for are then
  // refused as of unknown origin, never overwritten.
  const nlohmann::json js = nlohmann::json::parse(read_file_bytes(record.string()), nullptr, false);
  if (!js.is_object() || !js.contains("runs") || !js["runs"].is_object()) return;
  for (const auto& [name, source] : js["runs"].items())
    if (source.is_string()) sources_[name] = source.get<std::string>();
}

void ExportSources::check(const std::string& run) const {
  const std::string name = fs::path(run).stem().string();
  const std::vector<std::string> files = exported_files(dir_, name);
  if (files.empty()) return;
  const auto it = sources_.find(name);
  if (it != sources_.end() && same_file(it->second, run)) return;
  const std::string example = (fs::path(dir_) / files.front()).string();
  const std::string more =
      files.size() > 1 ? " and " + std::to_string(files.size() - 1) + " more files" : "";
  const std::string origin =
      it != sources_.end()
          ? "exported from the run '" + it->second + "'"
          : "whose run is not recorded (" + std::string(kExportSourcesFile) + " does not name it)";
  fail("--out '", dir_, "' already holds '", example, "'", more, ", ", origin, "; the run '", run,
       "' has the same name, and its files would replace them. Export it into "
       "another folder, or remove those files first");
}

void ExportSources::record(const std::vector<std::string>& runs) {
  for (const std::string& run : runs) sources_[fs::path(run).stem().string()] = absolute(run);
  nlohmann::json js;
  js["runs"] = nlohmann::json::object();
  for (const auto& [name, source] : sources_) js["runs"][name] = source;
  write_file_atomic((fs::path(dir_) / kExportSourcesFile).string(), js.dump(2) + "\n");
}

}  // namespace nsf::app
