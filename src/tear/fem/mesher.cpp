#include "tear/fem/mesher.h"

#include "tear/exec/plugin.h"

namespace tear {

const NetgenModule& netgen_module() {
  return *reinterpret_cast<const NetgenModule*>(
      load_plugin(TEAR_NETGEN_FILE, TEAR_NETGEN_ENTRY, kNetgenAbi,
                  "FEM bodies are meshed by the netgen module", "tear_netgen"));
}

}  // namespace tear
