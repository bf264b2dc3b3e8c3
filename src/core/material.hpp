// A material: what a particle or a wall is made of. Contact laws live on
// material pairs (see contact/pair_table.hpp); the material itself carries
// only bulk properties.
#pragma once

#include <string>

namespace granule {

struct Material {
  std::string name;
  double density = 0;         // kg/m^3 (walls may leave it 0)
  double young = 0;           // Pa, 0 = not given
  double poisson = 0;         // -
  double surface_energy = 0;  // J/m^2
};

}  // namespace granule
