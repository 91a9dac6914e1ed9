#pragma once
// Which run file the files of `nsf export` in a folder came from. Exported files are named after
// the run file's name (sand.h5 -> sand_0012.vtu, sand.pvd), so two runs of the same name from
// different folders (every sweep names its runs train_0.h5, test_0.h5, ...) would overwrite each
// other's files in one output folder. In an output folder a name therefore belongs to one run file:
// the export records it in DIR/.nsf-export.json, re-exporting that run file replaces its files, and
// exporting another run of the same name is refused, naming both, before anything is written.
#include <map>
#include <string>
#include <vector>

namespace nsf::app {

inline constexpr const char* kExportSourcesFile = ".nsf-export.json";

// The files in `dir` that an export of a run named `name` writes, in any format: name_NNNN.ply,
// .vtk and .vtu, name.pvd, name.vtk.series, name.series.xdmf and name.series.h5. Sorted.
std::vector<std::string> exported_files(const std::string& dir, const std::string& name);

class ExportSources {
 public:
  explicit ExportSources(std::string dir);  // reads dir/.nsf-export.json if it is there

  // Fails when `dir` already holds files of `run`'s name that were exported from another run file,
  // or from a run file that was not recorded, naming the files, both runs and the way out.
  void check(const std::string& run) const;
  // Records each run (as an absolute path) as the source of its name's files, and writes the
  // record atomically.
  void record(const std::vector<std::string>& runs);

 private:
  std::string dir_;
  std::map<std::string, std::string> sources_;  // run name -> absolute run file path
};

}  // namespace nsf::app
