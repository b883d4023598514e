#pragma once
// Where the picture is taken from: a view direction given as azimuth, elevation and roll, and
// a projection that fits a box (the volume, or a mesh's bounds) into the image.
//
// World axes are the volume's: x = column, y = row, z = slice, scaled by the voxel spacing.
// The default view (0, 0, 0) looks from the -y side (the top rows of a slice, where CT and MR
// put the front of the patient) towards +y, with +z (later slices) up and +x to the right.
// Azimuth turns the camera about the z axis towards +x; elevation lifts it towards +z; roll
// turns the picture counter-clockwise about the view direction. Angles are in degrees.
#include <cstdint>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace mvox {

struct ViewOptions {
  float azimuth_deg = 0;
  float elevation_deg = 0;
  float roll_deg = 0;
  bool perspective = false;      // orthographic by default
  float field_of_view_deg = 30;  // perspective only: vertical angle, in (0, 180)
  float margin = 0.04f;          // free border around the fitted box, a fraction of the image
  // A cutaway: the nearest `cut` of the box's depth along the view is cut away by a plane
  // facing the viewer, to show what lies inside (0: nothing cut, 0.5: through the centre).
  float cut = 0;
};

struct Camera {
  glm::mat4 world_to_clip{1.0f};  // OpenGL conventions: visible depth maps to -1 (near) .. 1
  glm::mat3 world_to_view{1.0f};  // rotation only: the viewer looks along -z of view space
  std::uint32_t width = 0;        // image size in pixels
  std::uint32_t height = 0;
  // Depth (0 near .. 1 far, as ZBufferRenderer keeps it) of the cutaway plane: nearer fragments
  // are not drawn. 0: no cut. A plane facing the viewer has one depth in both projections.
  float cut_depth = 0;
};

// The camera that shows the whole box [box_min, box_max] (world units) from `view` in an image
// of width x height pixels, centred and as large as the margin allows, with the same scale on
// both image axes. Orthographic: the box's projection is fitted exactly. Perspective: the
// camera stands back so that the box's bounding sphere fits the field of view. A cut in (0, 1]
// places the cutaway plane that far through the box's depth along the view.
Camera fit_camera(const glm::vec3& box_min, const glm::vec3& box_max, const ViewOptions& view,
                  std::uint32_t width, std::uint32_t height);

// The rotation from world to view space for `view` (no projection).
glm::mat3 view_rotation(const ViewOptions& view);

}  // namespace mvox
