#include "app/cli_help.h"

#include "core/isa.h"

#include <omp.h>
#include <torch/cuda.h>
#include <torch/version.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <sstream>

namespace nsf::app {

namespace {

// The long and short option names of a command, as typed ("--out", "-o").
std::vector<std::string> option_names(const CLI::App& cmd) {
  std::vector<std::string> out;
  for (const CLI::Option* o : cmd.get_options()) {
    for (const std::string& n : o->get_lnames()) out.push_back("--" + n);
    for (const std::string& n : o->get_snames()) out.push_back("-" + n);
  }
  return out;
}

std::vector<const CLI::App*> commands(const CLI::App& app) {
  std::vector<const CLI::App*> out;
  for (const CLI::App* c : app.get_subcommands([](const CLI::App*) { return true; }))
    if (!c->get_group().empty()) out.push_back(c);
  return out;
}

// roff text: a leading dot or quote would be read as a request, backslashes as escapes.
std::string roff(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\\') {
      out += "\\e";
    } else if (c == '-') {
      out += "\\-";
    } else {
      out += c;
    }
  }
  if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out = "\\&" + out;
  return out;
}

}  // namespace

std::string version_text() {
  std::ostringstream s;
  s << "nsf " << NSF_VERSION << "\n";
  s << "commit: " << NSF_GIT_COMMIT << "\n";
#if defined(__clang__)
  s << "compiler: clang " << __clang_major__ << "." << __clang_minor__ << "\n";
#elif defined(__GNUC__)
  s << "compiler: gcc " << __GNUC__ << "." << __GNUC_MINOR__ << "." << __GNUC_PATCHLEVEL__ << "\n";
#endif
  s << "build: " << NSF_BUILD_TYPE << ", C++" << __cplusplus / 100 % 100 << "\n";
  s << "instruction set:";
#if defined(__AVX512F__)
  s << " AVX-512";
#elif defined(__AVX2__)
  s << " AVX2";
#elif defined(__SSE4_2__)
  s << " SSE4.2";
#else
  s << " baseline";
#endif
#if defined(__FMA__)
  s << " FMA";
#endif
  s << "\n";
  s << "hot kernels (P2G, G2P, the ROM's products): " << kernel_isa() << "\n";
  s << "OpenMP: " << _OPENMP << ", " << omp_get_num_procs() << " processors here\n";
  s << "LibTorch: " << TORCH_VERSION << "\n";
  s << "CUDA: "
    << (torch::cuda::is_available()
            ? "available (" + std::to_string(torch::cuda::device_count()) + " devices)"
            : std::string("not available (a CPU build, or no device here)"));
  return s.str();
}

std::string nearest_name(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = 3;
  for (const std::string& c : candidates) {
    // Levenshtein distance, one row at a time.
    std::vector<size_t> row(c.size() + 1);
    for (size_t j = 0; j <= c.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= word.size(); ++i) {
      size_t diagonal = row[0];
      row[0] = i;
      for (size_t j = 1; j <= c.size(); ++j) {
        const size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (word[i - 1] != c[j - 1])});
        diagonal = up;
      }
    }
    const size_t d = word.size() >= 3 && c.compare(0, word.size(), word) == 0 ? 1 : row.back();
    if (d < best_distance) best_distance = d, best = c;
  }
  return best;
}

std::string unknown_option(const CLI::App& command, const std::vector<std::string>& args) {
  const std::vector<std::string> names = option_names(command);
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--") break;
    if (arg.size() < 2 || arg[0] != '-') continue;
    char* end = nullptr;
    std::strtod(arg.c_str(), &end);
    if (end && *end == '\0') continue;  // a negative number
    // "--out=x" names --out; "-j2" names -j.
    const bool is_long = arg[1] == '-';
    const std::string name = is_long ? arg.substr(0, arg.find('=')) : arg.substr(0, 2);
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      const std::string near = nearest_name(name, names);
      return "'" + name + "' is not an option of 'nsf " + command.get_name() + "'" +
             (near.empty() ? "" : "; did you mean '" + near + "'?");
    }
    // Its value, when given as the next word, may begin with '-' ("--range -3:").
    const CLI::Option* o = command.get_option_no_throw(name);
    const bool value_attached = is_long ? arg.find('=') != std::string::npos : arg.size() > 2;
    if (o && o->get_items_expected_min() > 0 && !value_attached) ++i;
  }
  return "";
}

std::string bash_completion(const CLI::App& app) {
  std::ostringstream s;
  s << "# bash completion for nsf (nsf completion bash > "
       "~/.local/share/bash-completion/completions/nsf)\n"
    << "_nsf() {\n"
    << "  local cur=\"${COMP_WORDS[COMP_CWORD]}\" cmd=\"${COMP_WORDS[1]}\" words\n"
    << "  if [ \"$COMP_CWORD\" -eq 1 ]; then\n"
    << "    words=\"";
  for (const CLI::App* c : commands(app)) s << c->get_name() << " ";
  s << "--help --version\"\n"
    << "    COMPREPLY=($(compgen -W \"$words\" -- \"$cur\"))\n"
    << "    return\n"
    << "  fi\n"
    << "  case \"$cmd\" in\n";
  for (const CLI::App* c : commands(app)) {
    s << "    " << c->get_name() << ") words=\"";
    for (const std::string& n : option_names(*c)) s << n << " ";
    s << "\" ;;\n";
  }
  s << "    *) words=\"\" ;;\n"
    << "  esac\n"
    << "  if [[ \"$cur\" == -* ]]; then\n"
    << "    COMPREPLY=($(compgen -W \"$words\" -- \"$cur\"))\n"
    << "  else\n"
    << "    COMPREPLY=($(compgen -f -- \"$cur\"))\n"
    << "  fi\n"
    << "}\n"
    << "complete -o filenames -F _nsf nsf\n";
  return s.str();
}

std::string man_page(const CLI::App& app) {
  std::ostringstream s;
  s << ".TH NSF 1 \"\" \"nsf " << NSF_VERSION << "\" \"User Commands\"\n"
    << ".SH NAME\nnsf \\- "
    << roff(app.get_description().substr(app.get_description().find(": ") + 2)) << "\n"
    << ".SH SYNOPSIS\n.B nsf\n.I command\n[\\fIoptions\\fR]\n"
    << ".SH DESCRIPTION\nA full-order Material Point Method engine, the training of neural stress "
       "fields on its runs, and reduced-order simulation in their latent space. Each command "
       "below prints its own options with \\fB\\-\\-help\\fR.\n"
    << ".SH COMMANDS\n";
  for (const CLI::App* c : commands(app)) {
    s << ".SS " << c->get_name() << "\n" << roff(c->get_description()) << "\n";
    for (const CLI::Option* o : c->get_options()) {
      if (o->get_name().empty() || o == c->get_help_ptr()) continue;
      s << ".TP\n.B " << roff(o->get_name(false, true)) << "\n"
        << roff(o->get_description().empty() ? "(no description)" : o->get_description()) << "\n";
    }
  }
  s << ".SH EXIT STATUS\n0 success, 1 error, 2 usage error, 3 internal error.\n"
    << ".SH SEE ALSO\nThe documentation in the source tree's docs/ (README.md first).\n";
  return s.str();
}

void add_self_description_commands(CLI::App& app) {
  auto shell = std::make_shared<std::string>("bash");
  CLI::App* completion =
      app.add_subcommand("completion", "Print a shell completion script (bash) for nsf");
  completion->add_option("shell", *shell, "The shell")->check(CLI::IsMember({"bash"}));
  completion->callback([&app, shell] { std::cout << bash_completion(app); });
  CLI::App* man = app.add_subcommand("man", "Print nsf's manual page (roff; man -l - reads it)");
  man->callback([&app] { std::cout << man_page(app); });
}

}  // namespace nsf::app
