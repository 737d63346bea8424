#include "geometry/materials.h"

namespace ishibashi {

Material nishida_stone() {
  Material m;
  m.name = "stone";
  m.density_kg_m3 = 1.88e3;
  m.young_pa = 1.4039e10;
  m.poisson = 0.28;
  m.friction_deg = 33.23;
  m.damping_normal = 1.0;
  m.damping_shear = 1.0;
  return m;
}

Material nishida_soil() {
  Material m;
  m.name = "soil";
  m.density_kg_m3 = 1.8e3;
  m.young_pa = 1.9e8;
  m.poisson = 0.3;
  m.friction_deg = 30.0;
  m.damping_normal = 1.0;
  m.damping_shear = 1.0;
  return m;
}

}  // namespace ishibashi
