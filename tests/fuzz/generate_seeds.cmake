# SPDX-License-Identifier: MIT
# Writes the seed inputs that are too large to keep in git into OUT:
#   cmake -DOUT=<dir> -P tests/fuzz/generate_seeds.cmake
# (tests/CMakeLists.txt runs it at configure time into <build>/tests/fuzz/generated).
# Each is a construct of issue 12 that breaks Coin 4.0's reader; the guard must refuse it.
if(NOT OUT)
  message(FATAL_ERROR "usage: cmake -DOUT=<dir> -P generate_seeds.cmake")
endif()
file(MAKE_DIRECTORY "${OUT}")
set(header "#Inventor V2.1 ascii\n")

# Identifiers of 65,504 characters and more overflow the 65,504-byte chunks of Coin's name table.
string(REPEAT "A" 65504 name)
file(WRITE "${OUT}/long_def_name.iv" "${header}DEF ${name} Separator { }\n")
file(WRITE "${OUT}/long_type_name.iv" "${header}Separator { ${name} { } }\n")
file(WRITE "${OUT}/long_field_name.iv" "${header}Separator { Cube { ${name} 1 } }\n")
file(WRITE "${OUT}/long_name_string.iv" "${header}Separator { Label { label \"${name}\" } }\n")
string(REPEAT "B" 70000 name)
file(WRITE "${OUT}/long_def_name_70000.iv" "${header}DEF ${name} Separator { }\n")

# Coin's recursive reader overflows an 8 MB stack at about 11,600 nested groups.
string(REPEAT "Separator {\n" 12000 open)
string(REPEAT "}\n" 12000 close)
file(WRITE "${OUT}/nested_separators_12000.iv" "${header}${open}${close}")
