# Writes INPUT's text into OUTPUT as a C++ raw string literal named NAME (cmake -P script).
file(READ "${INPUT}" content)
file(WRITE "${OUTPUT}" "// Generated from ${INPUT}; do not edit.\ninline constexpr char ${NAME}[] = R\"fovlab_text(${content})fovlab_text\";\n")
