// Projected (nonsmooth) Gauss-Seidel over the contacts (Jean & Moreau's NSGS): contact
// a's problem u_a = W_aa r_a + v_a, v_a = q_a + sum_{b != a} W_ab r_b, with the other
// forces frozen, solved by a local Alart-Curnier Newton iteration on the d x d system.
#pragma once

#include <vector>

#include "block_delassus.hpp"
#include "ncp/fc/problem.hpp"

namespace ncp::fc::internal {

/// One sweep over the contacts in order, updating *r in place. A contact's new force is
/// kept only when it lowers that contact's natural-map residual |r_a - P_C(r_a -
/// u_hat_a)|. rho: the Alart-Curnier parameters per contact (Rho::n, Rho::t).
void GaussSeidelSweep(const FrictionProblem& problem, const BlockDelassus& W,
                      const std::vector<Rho>& rho, Vector* r);

}  // namespace ncp::fc::internal
