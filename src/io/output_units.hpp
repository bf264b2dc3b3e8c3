// The unit of every quantity the output writes under a fixed name: the snapshot
// datasets, the contact network, the /series columns and the columns diagnostics
// commonly share. H5Output writes it as the "units" attribute of each dataset;
// tools read it back for their legends. SI; "-" dimensionless (a count, an id, an
// index, a ratio); "" not known.
#pragma once

#include <cstring>
#include <string>

namespace granule::io {

struct QuantityUnit {
  const char* name;
  const char* unit;
};

inline constexpr QuantityUnit quantity_units[] = {
    // snapshots
    {"id", "-"},
    {"radius", "m"},
    {"position", "m"},
    {"velocity", "m/s"},
    {"spin", "rad/s"},
    {"material", "-"},
    {"fixed", "-"},
    {"force", "N"},
    {"torque", "N m"},
    // the contact network of a snapshot (/snapshots/NNNNNN/contacts)
    {"i", "-"},
    {"j", "-"},
    {"wall", "-"},
    {"overlap", "m"},
    {"normal_force", "N"},
    {"tangential_force", "N"},
    {"normal", "-"},
    // /series, and the columns diagnostics share
    {"time", "s"},
    {"step", "-"},
    {"kinetic_energy", "J"},
    {"kinetic_energy_translational", "J"},
    {"kinetic_energy_rotational", "J"},
    {"contacts_particle", "-"},
    {"contacts_wall", "-"},
    {"max_overlap_ratio", "-"},
    {"momentum_x", "kg m/s"},
    {"momentum_y", "kg m/s"},
    {"momentum_z", "kg m/s"},
    {"angular_momentum_z", "kg m^2/s"},
    {"force_x", "N"},
    {"force_y", "N"},
    {"force_z", "N"},
    {"samples", "-"},
};

// The unit of a quantity by the name the output gives it; "" when the table has none.
inline const char* unit_of(const std::string& name) {
  for (const auto& q : quantity_units)
    if (name == q.name) return q.unit;
  return "";
}

}  // namespace granule::io
