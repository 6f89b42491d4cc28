// The suite's two absolute paths: the source tree and the rotleak command of this build. They are
// compiled into one small object (tests/paths.cpp) so that no other test's command line names where the
// tree lies, and a clone at another path reuses the compiler cache for every other object.
#pragma once

namespace rotleak::test {

const char* source_dir();      // the source tree (data/, scripts/)
const char* rotleak_binary();  // the rotleak command built beside the tests

}  // namespace rotleak::test
