// driver/: `tear mesh`: the surface mesh of each frame of a run folder, DIR/meshes/NNNNN.obj
// (and/or .ply), through surface/mesher.h (docs/cli.md, docs/outputs.md).
#pragma once

#include <string>
#include <vector>

namespace tear {

struct MeshFramesOptions {
  std::string dir;     // a run folder (DIR/frames/)
  std::string frames;  // "A:B", "A:", ":B", "A" or "" (all)
  double spacing = 0;  // 0: estimated from the run's first frame (its sampling lattice)
  double radius = 0;   // in spacings; 0: the mesher's default
  double voxel = 0;    // in spacings; 0: the mesher's default
  int smooth = -1;     // -1: the mesher's default
  double damage_threshold = 0.5;
  std::vector<std::string> formats{"obj"};  // obj, ply
  int threads = 0;                          // 0: all cores
  bool quiet = false;
};

// `tear mesh`. Returns the exit code (1: bad input, 2: a malformed --frames); errors are one
// line "tear: reason" on stderr, progress lines go to stderr and a summary to stdout.
int mesh_frames(const MeshFramesOptions& options);

}  // namespace tear
