# Warnings are errors in our own code (never in generated or third-party code).
function(swarmform_target_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                           -Wno-sign-conversion -Wnon-virtual-dtor)
  if(SWARMFORM_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
