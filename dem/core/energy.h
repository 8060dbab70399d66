// Energy bookkeeping. With leapfrog velocities at half steps, the kinetic energy at step n is
// taken as 1/2 m v(n-1/2).v(n+1/2): for linear springs this makes kinetic + elastic energy an exact
// invariant of the undamped scheme (a short derivation is in docs/dem.md), so that the balance
//   kinetic + elastic + gravity potential + dissipated - external work = const
// closes to round-off for linear laws and to O(dt^2) otherwise.
#pragma once

namespace anticrack::dem
{
  struct EnergyLedger
  {
    // --- state functions (recomputed on demand)
    double kinetic = 0;
    double elastic_contacts = 0;
    double elastic_bonds = 0;
    double gravity_potential = 0; ///< -sum m g.x (relative to the origin)
    // --- path functions (accumulated every step)
    double friction = 0;          ///< dissipated by Coulomb sliding
    double viscous = 0;           ///< dissipated by dashpots
    double local_damping = 0;     ///< dissipated by Cundall local damping
    double bond_breakage = 0;     ///< elastic energy released by broken bonds
    double external_work = 0;     ///< by walls, applied clump forces and prescribed velocities

    [[nodiscard]] double stored() const
    {
      return kinetic + elastic_contacts + elastic_bonds + gravity_potential;
    }
    [[nodiscard]] double dissipated() const
    {
      return friction + viscous + local_damping + bond_breakage;
    }
    /// Should stay equal to its initial value.
    [[nodiscard]] double balance() const { return stored() + dissipated() - external_work; }
  };
} // namespace anticrack::dem
