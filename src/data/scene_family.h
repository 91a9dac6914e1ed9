#pragma once
// The scenes a model's training runs simulated, value by value (issue #55 item 4): each number of
// the scene file (a JSON leaf such as /colliders/1/motion/keyframes/1/t) with the range it took
// over the runs, each other value with the values it took. A run whose scene holds a number
// outside its range, another value, or a key the runs never had is not one of the family the
// latent space was trained on, whatever the sweep calls its parameters: a faster collider, a
// tilted floor, a thrown object, a second collider. The reduced-order runtime says so
// (rom/setup/rom_setup.h) and may run such a scene with the settings of the scene's "unseen"
// profile.
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace nsf {

class SceneFamily {
 public:
  // One run's scene, as the run file stores it (the sweep's templates applied). The keys that
  // do not change what is simulated are left out: name, description, camera, simulation.cfl and
  // the rom, train, sweep and generalize sections.
  static SceneFamily of(const nlohmann::json& scene);

  bool empty() const { return runs_ == 0; }
  int runs() const { return runs_; }
  size_t values() const { return leaves_.size(); }
  size_t varying() const;  // the values that differ between the runs
  // Grows this family to hold `other`'s runs too.
  void include(const SceneFamily& other);

  // What of `scene` lies outside the family, one line per value, e.g. "/colliders/1/motion/
  // keyframes/1/t = 0.17, outside [0.2, 0.2] (the training runs)"; empty when it lies inside (or
  // the family is empty: a model that never recorded it). A number may differ from the range by
  // a relative 1e-6 (rounding of the sweep's templates).
  std::vector<std::string> outside(const nlohmann::json& scene) const;

  nlohmann::json to_json() const;
  // Throws nsf::Error naming `where` when `j` is not what to_json writes.
  static SceneFamily from_json(const nlohmann::json& j, const std::string& where);

 private:
  struct Leaf {
    bool number = true;
    double lo = 0, hi = 0;            // numbers
    std::vector<std::string> values;  // other values, as JSON text, sorted
    bool every_run = true;            // every training run's scene holds it
  };
  std::map<std::string, Leaf> leaves_;  // by JSON pointer
  int runs_ = 0;
};

}  // namespace nsf
