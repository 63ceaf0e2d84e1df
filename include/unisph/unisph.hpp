#pragma once
// Everything of unisph's execution core in one include.

#include "unisph/core/config.hpp"
#include "unisph/core/error.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/dynamics/kernel_shell.hpp"
#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/atomic.hpp"
#include "unisph/exec/policy.hpp"
#include "unisph/exec/reduce_ops.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/memory/singular_variable.hpp"
#include "unisph/memory/view.hpp"
