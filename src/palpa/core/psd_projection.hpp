// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// How an indefinite Hessian is made positive semi-definite for Newton's
// method: None keeps the true Hessian (sensitivities, adjoints), Clamp sets
// negative eigenvalues to zero, Abs flips their sign. Materials project their
// stretch-space Hessians with it; the assembler (solve/assembler.hpp) takes it
// per call and hands it to every term.

namespace palpa {

enum class PsdProjection { None, Clamp, Abs };

}  // namespace palpa
