#include "mpm/scene/mesh/mesh_shape.h"

#include "mpm/scene/mesh/orientation.h"
#include "mpm/scene/mesh/winding_bvh.h"

namespace nsf {

namespace {

class MeshShape : public Shape {
 public:
  explicit MeshShape(const TriangleMesh& mesh) : bvh_(mesh) {}
  double sdf(const Vec3& p) const override {
    const double d = bvh_.distance(p);
    return bvh_.winding_number(p) >= 0.5 ? -d : d;
  }
  Aabb bounds() const override { return bvh_.bounds(); }

 private:
  WindingBvh bvh_;
};

}  // namespace

ShapePtr make_mesh_shape(TriangleMesh mesh) {
  orient_outward(mesh);
  return std::make_unique<MeshShape>(mesh);
}

}  // namespace nsf
