// Where rotleak finds what it ships beside its binary: the data (scenes, the study's inputs, the
// published tables, the reference trajectories) and the Python package (readers and plots). An
// installed rotleak (cmake --install, the .deb) finds them relative to its own binary, never through
// the source tree it was built from; a binary in its build tree uses that build and its sources.
#pragma once

#include <filesystem>

namespace rotleak {

/// The directory of the running program (/proc/self/exe); empty if unknown.
std::filesystem::path program_dir();

/// The data directory (holding scenes/, study/, literature/, trajectories/): $ROTLEAK_DATA when set
/// (it must exist); else PREFIX/share/rotleak/data for a binary in PREFIX/bin; else, for a binary in
/// its build directory (beside CMakeCache.txt), the source tree of that build. Otherwise an InputError
/// naming ROTLEAK_DATA.
std::filesystem::path data_dir();

/// The directory holding the Python package rotleak/ (for PYTHONPATH): $ROTLEAK_PYTHONPATH when set;
/// else PREFIX/lib/python3/dist-packages for a binary in PREFIX/bin; else BUILD/python for a binary
/// in its build tree BUILD. Otherwise an InputError naming ROTLEAK_PYTHONPATH.
std::filesystem::path python_dir();

}  // namespace rotleak
