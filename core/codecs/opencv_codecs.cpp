// The module that reads images in formats other than PNG and JPEG (TIFF,
// BMP, PNM, WebP, ...) through OpenCV's imgcodecs. lom_core loads it only
// when it meets such an image (core/src/other_images.cpp): imgcodecs and the
// 139 libraries it needs would otherwise cost every start of the programs a
// tenth of a second. The functions keep to C linkage for dlsym; the Mat they
// fill is the caller's (the same libopencv_core).
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

extern "C" {

// 1 with the image in *out, 0 with OpenCV's reason in `message` (or an empty
// message when it knows no decoder for the file).
__attribute__((visibility("default"))) int lom_codecs_imread(const char* path, int flags,
                                                             cv::Mat* out, char* message,
                                                             std::size_t message_size) {
  try {
    *out = cv::imread(path, flags);
    if (message_size) message[0] = '\0';
    return out->empty() ? 0 : 1;
  } catch (const cv::Exception& e) {
    std::snprintf(message, message_size, "%s", e.what());
    return 0;
  }
}

// 1 with the image in *out, 0 when OpenCV cannot decode the bytes.
__attribute__((visibility("default"))) int lom_codecs_imdecode(const unsigned char* data,
                                                               std::size_t size, int flags,
                                                               cv::Mat* out) {
  try {
    const cv::Mat buffer(1, static_cast<int>(size), CV_8UC1, const_cast<unsigned char*>(data));
    *out = cv::imdecode(buffer, flags);
    return out->empty() ? 0 : 1;
  } catch (const cv::Exception&) {
    return 0;
  }
}

}  // extern "C"
