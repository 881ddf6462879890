#pragma once
// Moved to study/log/schedule_check.h (export and analyze run it too); this name stays for the
// session and replay.
#include "study/log/schedule_check.h"
