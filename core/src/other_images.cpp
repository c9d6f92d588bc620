#include "other_images.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <mutex>
#include <system_error>
#include <vector>

#include "lom/error.hpp"

namespace lom {

namespace {

namespace fs = std::filesystem;

using ReadFn = int (*)(const char*, int, cv::Mat*, char*, std::size_t);
using DecodeFn = int (*)(const unsigned char*, std::size_t, int, cv::Mat*);

struct Codecs {
  ReadFn read = nullptr;
  DecodeFn decode = nullptr;
  std::string looked;  // where the module was looked for, when it was not found
};

constexpr const char* kModuleName = "liblom-opencv-codecs.so";

// Where `cmake --install` puts it beside an installed program
// (<prefix>/bin/../<libdir>/labeloctomap, whatever the prefix), next to the
// program, under the configured prefix, then where the build wrote it.
std::vector<fs::path> candidates() {
  std::vector<fs::path> paths;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
#ifdef LOM_CODECS_RELATIVE
    paths.push_back(exe.parent_path().parent_path() / LOM_CODECS_RELATIVE);
#endif
    paths.push_back(exe.parent_path() / kModuleName);
  }
#ifdef LOM_CODECS_INSTALLED
  paths.emplace_back(LOM_CODECS_INSTALLED);
#endif
#ifdef LOM_CODECS_BUILT
  paths.emplace_back(LOM_CODECS_BUILT);
#endif
  return paths;
}

const Codecs& codecs() {
  static Codecs loaded;
  static std::once_flag once;
  std::call_once(once, [] {
    const auto missed = [](const fs::path& path, const std::string& why) {
      loaded.looked += (loaded.looked.empty() ? "" : ", ") + path.string() +
                       (why.empty() ? "" : " (" + why + ")");
    };
    for (const fs::path& path : candidates()) {
      std::error_code ec;
      if (!fs::is_regular_file(path, ec)) {
        missed(path, "");
        continue;
      }
      void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);  // kept loaded
      if (!module) {
        const char* why = dlerror();
        missed(path, why ? why : "cannot be loaded");
        continue;
      }
      loaded.read = reinterpret_cast<ReadFn>(dlsym(module, "lom_codecs_imread"));
      loaded.decode = reinterpret_cast<DecodeFn>(dlsym(module, "lom_codecs_imdecode"));
      if (loaded.read && loaded.decode) return;
      missed(path, "not this program's module");
      loaded.read = nullptr;
      loaded.decode = nullptr;
    }
  });
  return loaded;
}

const Codecs& requireCodecs(const std::string& file) {
  const Codecs& c = codecs();
  if (!c.read)
    throw Error(file, "",
                "a PNG or JPEG image (other formats are read by " + std::string(kModuleName) +
                    ", installed with the programs)",
                "an image of another format, and no module to read it: looked for " + c.looked);
  return c;
}

}  // namespace

cv::Mat readOtherImage(const std::string& file, int flags) {
  const Codecs& c = requireCodecs(file);
  cv::Mat mat;
  char message[512] = {};
  if (c.read(file.c_str(), flags, &mat, message, sizeof(message))) return mat;
  if (message[0])
    throw Error(file, "", "a readable image", "OpenCV failed: " + std::string(message));
  throw Error(file, "", "a readable image", "a file OpenCV cannot decode");
}

cv::Mat decodeOtherImage(const std::uint8_t* data, std::size_t size, int flags,
                         const std::string& what) {
  const Codecs& c = requireCodecs(what);
  cv::Mat mat;
  if (!c.decode(data, size, flags, &mat)) return {};
  return mat;
}

}  // namespace lom
