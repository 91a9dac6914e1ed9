#pragma once
// Refuses an output path that names one of the command's inputs, or another of its outputs:
// `nsf simulate s.json --out s.json` used to replace the scene by the run, with exit 0. Paths
// compare as files, not as strings: through symlinks, "..", "./" and hard links; a path that does
// not exist yet compares by std::filesystem::weakly_canonical.
#include <string>
#include <vector>

namespace nsf {

struct NamedPath {
  std::string role;  // how the message names it: "--out", "the scene", "--fom-out"
  std::string path;  // empty: not given, skipped
};

// Whether a and b name the same file (or would, once made).
bool same_file(const std::string& a, const std::string& b);

// Throws nsf::Error ("--out 's.json' is the same file as the scene 's.json': ...") when an
// output is an input or another output.
void refuse_path_clash(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs);

}  // namespace nsf
