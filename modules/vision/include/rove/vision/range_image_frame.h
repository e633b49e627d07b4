#pragma once
/// \file
/// RGB-D frames from 3D range observations (rove/obs/range_image_3d.h,
/// MRPT's CObservation3DRangeScan): the intensity image as the frame's color
/// and the depth image registered to it, so that the RGB-D pipeline sees one
/// camera, the intensity camera.

#include "rove/obs/range_image_3d.h"
#include "rove/vision/rgbd_frame.h"

namespace rove {

/// The RGB-D frame of a 3D range observation, in its intensity camera
/// (observation.intensity_camera): color = the intensity image (8-bit gray
/// or RGB, as stored); depth = the depth image registered to it, float
/// meters (scale 1). Registration: every valid pixel of the depth image
/// (RangeImage3D::project, depth or range, max_range applied) is a point in
/// the depth camera's optical frame, carried into the intensity camera's
/// optical frame by T_intensity_depth = T_sensor_intensity⁻¹ ·
/// sensor_from_optical(), and projected by the intensity camera (with its
/// distortion) to its nearest pixel, which keeps the nearest such point's z
/// (a z-buffer: a surface hidden from the intensity camera does not show
/// through). Pixels no point reaches have no depth (0): those outside the
/// depth camera's view, and a few inside it where the depth camera's pixels
/// are coarser than the intensity camera's. With both cameras equal and
/// T_sensor_intensity = sensor_from_optical(), the depth image comes back
/// as it was (in meters).
///
/// Preconditions (InvalidArgument): observation.check() passes; it has a
/// depth image and an intensity image of 8-bit samples with 1 or 3
/// channels, whose size equals intensity_camera's when that states one.
RgbdFrame rgbd_frame_from_range_image(const RangeImage3D& observation);

/// The intensity camera of `observation` with its width and height set
/// from the intensity image when the camera states none.
/// Precondition (InvalidArgument): the observation has an intensity image.
PinholeCamera intensity_camera_of(const RangeImage3D& observation);

}  // namespace rove
