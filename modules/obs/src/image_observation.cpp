#include "rove/obs/image_observation.h"

#include "rove/core/check.h"

namespace rove {

void ImageObservation::check() const {
  image.check();
  if (camera.width != 0 || camera.height != 0) {
    ROVE_CHECK_MSG(camera.width == image.width && camera.height == image.height,
                   "ImageObservation: camera is {}x{} but the image is {}x{}", camera.width,
                   camera.height, image.width, image.height);
  }
}

bool operator==(const ImageObservation& a, const ImageObservation& b) {
  return a.header_equals(b) && a.camera == b.camera && a.image == b.image;
}

void ImageObservation::save_payload(OutArchive& ar) const {
  save_header(ar);
  save(ar, camera);
  save(ar, image);
}

void ImageObservation::load_payload(InArchive& ar, std::uint8_t /*version 1*/) {
  load_header(ar);
  load(ar, camera);
  load(ar, image);
}

}  // namespace rove
