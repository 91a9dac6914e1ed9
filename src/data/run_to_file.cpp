#include "data/run_to_file.h"

#include "io/run_writer.h"

namespace nsf {

void run_to_file(Simulation& sim, const std::string& path, const RunAttributes& attributes,
                 const FrameCallback& on_frame, const RunWriterOptions& options) {
  const SimSettings& s = sim.settings();
  RunWriter writer(path, sim.particles(), s, sim.scene().name, sim.scene().source.dump(), options);
  for (const auto& [name, value] : attributes.numbers) writer.set_attribute(name, value);
  for (const auto& [name, value] : attributes.strings) writer.set_attribute(name, value);
  writer.write_frame(sim.particles(), sim.time());
  for (int f = 1; f <= s.frames; ++f) {
    sim.advance_frame();
    writer.write_frame(sim.particles(), sim.time());
    if (on_frame) on_frame(f);
  }
  writer.finish();
}

}  // namespace nsf
