# shatter_add_module(<name> <sources>...): an engine-independent library shatter_<name>
# (alias and exported name shatter::<name>) whose headers are included as "plugin/<name>/X.h".
function(shatter_add_module name)
  add_library(shatter_${name} ${ARGN})
  add_library(shatter::${name} ALIAS shatter_${name})
  set_target_properties(shatter_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(shatter_${name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/shatter>)
endfunction()
