#pragma once
// Switches only a test turns on in a stepper: each costs a brute-force pass per step, or undoes
// an optimisation, to check it against the plain way. No command, scene or host reaches them
// (they are not RomOptions); tests/unit/rom/eval/test_rom_end_to_end.cpp sets them on a stepper it
// has made.

namespace nsf {

class LatentStepper;

struct StepperChecks {
  // Also find N by brute force (g on every particle) each step and count the particles the
  // candidate scheme missed (RomDiagnostics::integration_misses).
  bool verify_integration_set = false;
  // Hand the engine N's constant data (rest position, mass, volume, material) every step, not
  // only when N differs from the last step's list. The results are the same bit for bit.
  bool refill_constant_data = false;
};

// From the next step on.
void set_stepper_checks(LatentStepper& stepper, const StepperChecks& checks);

}  // namespace nsf
