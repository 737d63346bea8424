// The materials of the Nishida Bridge study (MODEL.md section 4): dry joints, critical
// damping. Mortar is set per run (BridgeSpec::mortar_pa).
#pragma once
#include "engine/model.h"

namespace ishibashi {

Material nishida_stone();
Material nishida_soil();

}  // namespace ishibashi
