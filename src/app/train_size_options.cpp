#include "app/train_size_options.h"

#include "app/option_checks.h"

namespace nsf::app {

void add_train_size_options(CLI::App* cmd, TrainSizeArgs& args, const std::string& steps_default,
                            const std::string& widths_default) {
  add_list_option<long>(
      cmd, "--steps", args.steps,
      "Optimiser steps per stage: one value or g,h,l (default " + steps_default + ")", 1,
      1000000000);
  add_list_option(cmd, "--widths", args.widths,
                  "Hidden widths of the decoders: one value or g,h,l; 0 keeps the default (" +
                      widths_default + ")",
                  0, 65536);
}

void require_one_or_three(size_t count, const std::string& option, const std::string& what) {
  if (count != 1 && count != 3)
    throw CLI::ValidationError(option, "takes one value for every " + what +
                                           " or three (g,h,l), got " + std::to_string(count));
}

}  // namespace nsf::app
