#include "app/retired_options.h"

#include "rom/fields/field_source.h"

namespace nsf::app {

namespace {

struct RetiredOption {
  const char* command;
  const char* flag;
  const char* record;  // under docs/experiments/
};

// Each record names the commit where the code last lived (6a0656ca4713 for most).
constexpr RetiredOption kRetired[] = {
    {"rom", "--linearize", "2026-11-22-tangent-cache.md"},
    {"rom", "--flip", "2026-11-25-flip-correction.md"},
    {"rom", "--gn-threads", "2026-11-23-gn-threads.md"},
    {"report", "--flip", "2026-11-25-flip-correction.md"},
    {"train", "--mix-frames", "2026-11-23-jelly-encoder-overfits.md"},
    {"train", "--rom-latents", "2026-11-25-rom-latents.md"},
};

std::string retired_message(const std::string& what, const std::string& record) {
  return what + " was retired (it lost: docs/experiments/" + record + ")";
}

}  // namespace

void add_retired_options(CLI::App* cmd, const std::string& command) {
  for (const RetiredOption& r : kRetired) {
    if (command != r.command) continue;
    const std::string message = retired_message(r.flag, r.record);
    // With or without a value; refused as soon as it is read, before anything else is checked.
    cmd->add_option(
           r.flag,
           [message](const CLI::results_t&) -> bool { throw CLI::ValidationError(message); }, "")
        ->expected(0, 1)
        ->trigger_on_parse()
        ->group("");
  }
}

CLI::Validator not_a_retired_source(const std::string& role) {
  return CLI::Validator(
      [role](std::string& input) -> std::string {
        const std::string record = retired_field_source(role, input);
        return record.empty() ? std::string() : retired_message(input, record);
      },
      "");
}

}  // namespace nsf::app
