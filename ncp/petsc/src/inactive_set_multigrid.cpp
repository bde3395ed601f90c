// GridInterpolation: the interpolation between two grids of a nested iteration, made
// once.

#include "inactive_set_multigrid.hpp"

#include <string>

namespace ncp::petsc {

Mat GridInterpolation(DM coarse, DM fine) {
  PetscInt64 id = 0;
  NCP_PETSC_CHECK(PetscObjectGetId(reinterpret_cast<PetscObject>(coarse), &id));
  const std::string key = "ncp_petsc_interpolation_from_" + std::to_string(id);
  PetscObject kept = nullptr;
  NCP_PETSC_CHECK(
      PetscObjectQuery(reinterpret_cast<PetscObject>(fine), key.c_str(), &kept));
  // Made collectively when any rank lacks it (DMCreateInterpolation is collective).
  if (!AnyRank(PetscObjectComm(reinterpret_cast<PetscObject>(fine)), kept == nullptr))
    return reinterpret_cast<Mat>(kept);
  Mat P = nullptr;
  NCP_PETSC_CHECK(DMCreateInterpolation(coarse, fine, &P, nullptr));
  NCP_PETSC_CHECK(PetscObjectCompose(reinterpret_cast<PetscObject>(fine), key.c_str(),
                                     reinterpret_cast<PetscObject>(P)));
  Mat borrowed = P;
  NCP_PETSC_CHECK(MatDestroy(&P));  // `fine` holds it now
  return borrowed;
}

}  // namespace ncp::petsc
