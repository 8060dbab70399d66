#include "dem/core/clumps.h"

#include <Eigen/Eigenvalues>

namespace anticrack::dem
{
  Mat3 Clump::inverse_inertia_world() const
  {
    const Mat3 rotation = orientation.toRotationMatrix();
    return rotation * principal_inertia.cwiseInverse().asDiagonal() * rotation.transpose();
  }

  Clump make_clump(ParticleStore &particles, const std::vector<Index> &members, int clump_id)
  {
    if (members.empty())
      throw SetupError("make_clump: a clump needs at least one member");
    Clump clump;
    clump.members = members;
    Vec3 momentum = Vec3::Zero();
    for (const Index p : members)
    {
      if (p < 0 || p >= particles.size())
        throw SetupError("make_clump: member id " + std::to_string(p) + " out of range");
      if (particles.clump_id[p] >= 0)
        throw SetupError("make_clump: particle " + std::to_string(p) + " already belongs to a clump");
      clump.mass += particles.mass[p];
      clump.centre += particles.mass[p] * particles.position[p];
      momentum += particles.mass[p] * particles.velocity[p];
    }
    clump.centre /= clump.mass;
    clump.velocity = momentum / clump.mass;

    // Inertia tensor about the centre: each member a solid sphere, parallel-axis theorem.
    Mat3 inertia = Mat3::Zero();
    for (const Index p : members)
    {
      const Vec3 r = particles.position[p] - clump.centre;
      inertia += particles.inertia[p] * Mat3::Identity() +
                 particles.mass[p] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
    }
    Eigen::SelfAdjointEigenSolver<Mat3> eigen(inertia);
    Mat3 axes = eigen.eigenvectors();
    if (axes.determinant() < 0)
      axes.col(2) *= -1; // a proper rotation
    clump.principal_inertia = eigen.eigenvalues();
    clump.principal_frame = Quat(axes).normalized();
    clump.orientation = clump.principal_frame;
    for (const Index p : members)
    {
      clump.member_offset.push_back(axes.transpose() * (particles.position[p] - clump.centre));
      particles.clump_id[p] = clump_id;
    }
    return clump;
  }
} // namespace anticrack::dem
