# romp_source_commit(<source-dir> <out-var>): the commit romp's sources are from, 12 hex digits
# ("-dirty" appended when tracked files differ from it), or "unknown".
#
# Only a git checkout whose top is <source-dir> itself tells: the sources of a `git archive`
# unpacked inside another repository (a build folder on a GPU machine, a vendored copy) would
# otherwise report that repository's commit. An archive carries its commit instead in
# cmake/archive_commit.txt, which git fills in when it writes the archive (.gitattributes: export-subst).
function(romp_source_commit source_dir out_var)
  set(commit "unknown")
  execute_process(COMMAND git -C "${source_dir}" rev-parse --show-toplevel
    OUTPUT_VARIABLE top OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rc)
  if(rc EQUAL 0)
    file(REAL_PATH "${top}" top)
    file(REAL_PATH "${source_dir}" source)
  endif()
  if(rc EQUAL 0 AND top STREQUAL source)
    execute_process(COMMAND git -C "${source_dir}" rev-parse --short=12 HEAD
      OUTPUT_VARIABLE head OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rc)
    if(rc EQUAL 0 AND NOT head STREQUAL "")
      set(commit "${head}")
      execute_process(COMMAND git -C "${source_dir}" status --porcelain --untracked-files=no
        OUTPUT_VARIABLE dirty OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
      if(NOT dirty STREQUAL "")
        string(APPEND commit "-dirty")
      endif()
    endif()
  elseif(EXISTS "${source_dir}/cmake/archive_commit.txt")
    file(STRINGS "${source_dir}/cmake/archive_commit.txt" archived LIMIT_COUNT 1)
    if(archived MATCHES "^[0-9a-f]+$")  # in a checkout it still reads $Format:...$
      string(SUBSTRING "${archived}" 0 12 commit)
    endif()
  endif()
  set(${out_var} "${commit}" PARENT_SCOPE)
endfunction()
