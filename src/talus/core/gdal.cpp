#include "talus/core/gdal.hpp"

#include <dlfcn.h>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace talus::gdal {

const Module& module() {
  static const Module* loaded = nullptr;
  static std::once_flag once;
  static std::string why;
  std::call_once(once, [] {
    // Beside the program first (a copied build), then where the build wrote it.
    std::error_code ec;
    const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
    std::vector<std::string> places;
    if (!ec) places.push_back((self.parent_path() / "libtalus_gdal.so").string());
    if (places.empty() || places.front() != TALUS_GDAL_MODULE) places.push_back(TALUS_GDAL_MODULE);
    for (const std::string& place : places) {
      if (!std::filesystem::exists(place, ec)) {
        why += "\n  " + place + ": not there";
        continue;
      }
      void* handle = dlopen(place.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!handle) {
        const char* e = dlerror();
        why += "\n  " + place + ": " + (e ? e : "cannot be loaded");
        continue;
      }
      auto entry =
          reinterpret_cast<decltype(&talus_gdal_module)>(dlsym(handle, "talus_gdal_module"));
      if (!entry) {
        why += "\n  " + place + ": has no talus_gdal_module";
        dlclose(handle);
        continue;
      }
      const Module* m = entry();
      if (m->version != module_version) {
        why += "\n  " + place + ": built for another version of Talus (module layout " +
               std::to_string(m->version) + ", this program's " + std::to_string(module_version) +
               ")";
        dlclose(handle);
        continue;
      }
      loaded = m;
      return;
    }
  });
  if (!loaded)
    throw std::runtime_error("cannot load Talus's GDAL module (rasters, footprints and maps):" +
                             why);
  return *loaded;
}

} // namespace talus::gdal
