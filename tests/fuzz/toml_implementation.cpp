// toml++'s implementation (its parser and printer), compiled into the scene harness with the harness's
// instrumentation rather than linked from libtomlplusplus; tools/fuzz.sh builds it once per work folder.
#define TOML_IMPLEMENTATION
#include <toml++/toml.h>
