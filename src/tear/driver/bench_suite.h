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

}  // namespace tear
