function(lumar_set_warnings target)
  target_compile_options(${target} INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                             -Wcast-align -Woverloaded-virtual)
  if(LUMAR_WERROR)
    target_compile_options(${target} INTERFACE -Werror)
  endif()
endfunction()
