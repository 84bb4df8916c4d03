// driver/: the benchmark suite behind `tear bench`: figures as JSON, measured on this machine.
#pragma once

#include <nlohmann/json.hpp>

namespace tear {

// Stress evaluation cost per F, 3D: qr_aniso vs fixed_corotated over `evaluations` random F
// (a pool of random matrices is reused). Single thread.
nlohmann::json bench_stress(long evaluations);

// Explicit step throughput on a 3D elastic block of about `particles` particles (8 per cell on
// a 64^3 grid when particles = 475000) with `threads` threads: particle-steps per second,
// seconds per phase, bytes per particle.
nlohmann::json bench_step(long particles, int steps, int threads);

// Cost of the damage update on the same 3D block as bench_step, every particle damageable
// and pre-stretched past sigma_c (the worst case: the damage field is active everywhere):
// seconds per step with damage none / explicit / implicit and their ratio to none, plus the
// implicit CG iterations per solve.
nlohmann::json bench_damage(long particles, int steps, int threads);

// Cost per step of cloth and hair (Jiang et al. 2017), each next to the bench block of as many
// particles: a sheet of about `particles` vertex and element particles (2 vertices a cell
// along it; 100K triangles for 150000) and hair of 10 000 segments, falling; seconds per step
// and per phase, and the ratio to the solid.
nlohmann::json bench_codim(long particles, int steps, int threads);

}  // namespace tear
