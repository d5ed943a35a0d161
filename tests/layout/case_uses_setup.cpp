// case may not use setup: this must not build.
#include "talus/setup/setup.hpp"
