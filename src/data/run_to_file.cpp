#include "data/run_to_file.h"

#include "data/training_box.h"
#include "io/run_writer.h"

namespace nsf {

void run_to_file(Simulation& sim, const std::string& path, const RunAttributes& attributes,
                 const FrameCallback& on_frame, const RunWriterOptions& options) {
  const SimSettings& s = sim.settings();
  RunWriter writer(path, sim.particles(), s, sim.scene().name, sim.scene().source.dump(), options);
  for (const auto& [name, value] : attributes.numbers) writer.set_attribute(name, value);
  for (const auto& [name, value] : attributes.strings) writer.set_attribute(name, value);
  ColliderEnvelopeRecorder envelope;  // where the colliders went: the run's part of a model's box
  writer.write_frame(sim.particles(), sim.time());
  envelope.record(sim.colliders());
  for (int f = 1; f <= s.frames; ++f) {
    sim.advance_frame();
    writer.write_frame(sim.particles(), sim.time());
    envelope.record(sim.colliders());
    if (on_frame) on_frame(f);
  }
  writer.set_attribute("collider_envelope", envelope.box().to_json()["colliders"].dump());
  writer.finish();
}

}  // namespace nsf
