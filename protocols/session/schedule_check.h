#pragma once
// Moved to study/log/schedule_check.h (export and analyze run it too, on either reader's trials).
// This name stays only for protocols/session/session.cpp, until it includes that header itself.
#include "study/log/schedule_check.h"
