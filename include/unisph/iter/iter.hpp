#pragma once
// Hierarchical views (seed 002): containers of particles in frames and supercells, the View
// that walks them forward or backward, strided, nested and shared by a team, and the
// collective launch for teams. See docs/views.md.

#include "unisph/iter/collective_for.hpp"
#include "unisph/iter/collectivity.hpp"
#include "unisph/iter/container_traits.hpp"
#include "unisph/iter/direction.hpp"
#include "unisph/iter/frame.hpp"
#include "unisph/iter/runtime.hpp"
#include "unisph/iter/slot_ref.hpp"
#include "unisph/iter/supercell.hpp"
#include "unisph/iter/supercell_container.hpp"
#include "unisph/iter/view.hpp"
