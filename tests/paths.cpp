#include "paths.hpp"

namespace rotleak::test {

const char* source_dir() { return ROTLEAK_SOURCE_DIR; }
const char* rotleak_binary() { return ROTLEAK_BINARY; }

}  // namespace rotleak::test
