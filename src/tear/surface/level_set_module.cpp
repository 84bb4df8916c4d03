#include "tear/exec/plugin.h"
#include "tear/surface/level_set.h"

namespace tear {

const LevelSetModule& level_set_module() {
  return *reinterpret_cast<const LevelSetModule*>(
      load_plugin(TEAR_LEVEL_SET_FILE, TEAR_LEVEL_SET_ENTRY, kLevelSetAbi,
                  "the surface mesher needs its OpenVDB module", "tear_level_set"));
}

}  // namespace tear
