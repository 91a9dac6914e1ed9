#include "runtime/mlp_plugin_library.h"

#include <dlfcn.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>

#include "core/error.h"

namespace nsf {

namespace {

namespace fs = std::filesystem;

// The folder of the library holding this function: libnsf_runtime.so (or its hwcaps copy).
std::string runtime_dir() {
  Dl_info info{};
  if (!dladdr(reinterpret_cast<void*>(&runtime_dir), &info) || !info.dli_fname) return "";
  return fs::absolute(fs::path(info.dli_fname)).parent_path().string();
}

// The table of library `file`, opened and checked; null, with the reason in `why`, where it cannot
// be used.
const nsf_mlp_plugin* open_plugin(const std::string& file, std::string& why) {
  if (!fs::exists(file)) {
    why = "no such file";
    return nullptr;
  }
  void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* e = dlerror();
    why = e ? e : "dlopen failed";
    return nullptr;
  }
  auto entry = reinterpret_cast<nsf_mlp_plugin_entry>(dlsym(handle, NSF_MLP_PLUGIN_ENTRY));
  const nsf_mlp_plugin* t = entry ? entry() : nullptr;
  if (!t) {
    why = std::string("it has no ") + NSF_MLP_PLUGIN_ENTRY + " table";
  } else if (t->abi_version != NSF_MLP_PLUGIN_ABI_VERSION || t->size != sizeof(nsf_mlp_plugin)) {
    why = "its interface has version " + std::to_string(t->abi_version) + ", this runtime's " +
          std::to_string(NSF_MLP_PLUGIN_ABI_VERSION);
    t = nullptr;
  } else if (!t->nsf_version || std::strcmp(t->nsf_version, NSF_VERSION) != 0) {
    why = std::string("it is nsf ") + (t->nsf_version ? t->nsf_version : "?") +
          "'s, this runtime is nsf " + NSF_VERSION;
    t = nullptr;
  }
  return t;  // a refused library stays open: it may hold LibTorch, which does not unload
}

}  // namespace

std::vector<std::string> mlp_plugin_candidates(const char* env, const std::string& runtime_dir) {
  if (env && *env) return {env};
  fs::path dir(runtime_dir);
  // lib/glibc-hwcaps/x86-64-v3/ holds the runtime's copy alone: the plugin is the baseline's.
  if (dir.parent_path().filename() == "glibc-hwcaps") dir = dir.parent_path().parent_path();
  return {(dir / kMlpPluginFile).string(), (dir / "nsf" / kMlpPluginFile).string()};
}

const nsf_mlp_plugin& mlp_plugin(const std::string& model) {
  // The files opened so far: each model looks again (the variable may have changed), and a file
  // opened before is taken as it was.
  static std::mutex mutex;
  static std::map<std::string, const nsf_mlp_plugin*> opened;
  const std::lock_guard<std::mutex> lock(mutex);
  const char* env = std::getenv(kMlpPluginVariable);
  std::string tried;
  for (const std::string& file : mlp_plugin_candidates(env, runtime_dir())) {
    if (const auto it = opened.find(file); it != opened.end()) return *it->second;
    std::string why;
    if (const nsf_mlp_plugin* table = open_plugin(file, why)) return *(opened[file] = table);
    tried += "\n  " + file + ": " + why;
  }
  const std::string where =
      env && *env ? std::string(" (") + kMlpPluginVariable + " is set: there alone)" : "";
  fail("model file ", model,
       " is an MLP model (nsf train --decoder mlp), whose networks need LibTorch: the runtime "
       "evaluates them through its MLP plugin, ",
       kMlpPluginFile, ", and found none it could use. Looked for", where, ":", tried,
       "\nnsf builds the plugin when it builds with LibTorch (cmake -DNSF_WITH_TORCH=ON, the "
       "default), and cmake --install puts it in LIBDIR/nsf/; ",
       kMlpPluginVariable,
       " set to a path makes the runtime load that file. A model file without a run-time record "
       "may also be a basis model saved by an older nsf: rewrite it with `nsf upgrade ",
       model, "`");
}

}  // namespace nsf
