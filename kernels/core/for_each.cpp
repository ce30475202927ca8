// The launch shape's one setting from the environment (for_each.h).
#include <cstdlib>
#include <string>

#include "kernels/core/error.h"
#include "kernels/core/for_each.h"

namespace romp::detail {

int parse_block_size(const char* value) {
  if (value == nullptr || *value == '\0') return 0;
  char* end = nullptr;
  const long block = std::strtol(value, &end, 10);
  ROMP_CHECK(*end == '\0' && (block == 0 || (block >= 32 && block <= 1024 && block % 32 == 0)),
             std::string("ROMP_FOR_EACH_BLOCK_SIZE='") + value +
                 "': give 0 (the occupancy calculator's) or a multiple of 32 from 32 to 1024");
  return int(block);
}

int forced_block_size() {
  static const int block = parse_block_size(std::getenv("ROMP_FOR_EACH_BLOCK_SIZE"));
  return block;
}

}  // namespace romp::detail
