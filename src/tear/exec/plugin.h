// exec/: loading tear's own plug-in modules (shared objects built beside tear and opened on first
// use, so that a program that never needs their libraries does not pay for loading them):
// surface/'s OpenVDB half, fem/'s netgen mesher. Plain C entry points, checked by an interface
// number.
#pragma once

namespace tear {

// Every module's entry point returns a pointer to a struct whose first member is `int abi`.
struct PluginHeader {
  int abi;
};

// The module `file` (e.g. "libtear_level_set.so"), opened once per process and kept open, from
// $TEAR_MODULE_DIR where that is set, else from the running program's folder or, failing that,
// the build folder tear was built in (for the tests); returns what its `entry` function returns.
// Throws std::runtime_error naming each file tried and why it failed (no file, dlopen's error,
// no entry point, an interface number other than `abi`), starting with `purpose` ("the surface
// mesher needs its OpenVDB module") and ending with how to build it (`target`).
const PluginHeader* load_plugin(const char* file, const char* entry, int abi, const char* purpose,
                                const char* target);

}  // namespace tear
