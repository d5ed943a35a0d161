// solver may not use output: this must not build.
#include "talus/output/files.hpp"
