#include "core/path_clash.h"

#include <filesystem>
#include <system_error>

#include "core/error.h"

namespace nsf {

namespace fs = std::filesystem;

bool same_file(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return false;
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) {
    const bool same = fs::equivalent(a, b, ec);  // also hard links
    if (!ec) return same;
  }
  const fs::path ca = fs::weakly_canonical(a, ec);
  if (ec) return fs::absolute(a).lexically_normal() == fs::absolute(b).lexically_normal();
  const fs::path cb = fs::weakly_canonical(b, ec);
  if (ec) return fs::absolute(a).lexically_normal() == fs::absolute(b).lexically_normal();
  return ca == cb;
}

void refuse_path_clash(const std::vector<NamedPath>& outputs,
                       const std::vector<NamedPath>& inputs) {
  for (size_t i = 0; i < outputs.size(); ++i) {
    const NamedPath& out = outputs[i];
    if (out.path.empty()) continue;
    for (const NamedPath& in : inputs)
      if (same_file(out.path, in.path))
        fail(out.role, " '", out.path, "' is the same file as ", in.role, " '", in.path,
             "': writing it would destroy that input; choose another output path");
    for (size_t j = 0; j < i; ++j)
      if (same_file(out.path, outputs[j].path))
        fail(out.role, " '", out.path, "' is the same file as ", outputs[j].role, " '",
             outputs[j].path, "': one output would overwrite the other; give two paths");
  }
}

}  // namespace nsf
