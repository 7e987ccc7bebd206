#pragma once
/// \file mesh.h
/// Forwards to field/mesh/mesh.h, where the mesh layer lives (its own target,
/// rosy_mesh). Kept so that code outside field/ keeps compiling while its
/// includes move to the new path.
#include "field/mesh/mesh.h"
