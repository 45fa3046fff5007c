# shatter_add_module(<name> <sources>...): an engine-independent library shatter_<name>
# (alias and exported name shatter::<name>) whose headers are included as
# <shatter/plugin/<name>/X.h>. Every module may throw shatter::InputError (shatter::common);
# a module that uses another module links it by name.
function(shatter_add_module name)
  add_library(shatter_${name} ${ARGN})
  add_library(shatter::${name} ALIAS shatter_${name})
  set_target_properties(shatter_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(shatter_${name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(shatter_${name} PUBLIC shatter_common)
endfunction()
