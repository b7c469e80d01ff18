# SPDX-License-Identifier: GPL-2.0-or-later
# Copies LIGGGHTS' src/ into the build tree, applies the fixes that GCC 12
# needs there, and writes the style_*.h registries (what `Make.sh style` does)
# so that they list the stock styles and ours from src_liggghts_plugin/.

# In the text of variable `var`, replace `from` by `to`; fail loudly if the
# text is not there, so that a LIGGGHTS version we were not written for is
# noticed.
function(_crush_patch var from to)
  string(FIND "${${var}}" "${from}" _pos)
  if(_pos EQUAL -1)
    message(FATAL_ERROR "Cannot patch LIGGGHTS source: text not found: ${from}")
  endif()
  string(REPLACE "${from}" "${to}" _text "${${var}}")
  set(${var} "${_text}" PARENT_SCOPE)
endfunction()

# Write `content` to `file` only when it differs, so unchanged registries do
# not trigger recompiles.
function(_crush_write_if_changed file content)
  if(EXISTS "${file}")
    file(READ "${file}" _old)
    if(_old STREQUAL content)
      return()
    endif()
  endif()
  file(WRITE "${file}" "${content}")
endfunction()

function(prepare_liggghts_source src dst plugin_dir)
  set(_stamp "${dst}/.copied_from")
  set(_need_copy TRUE)
  if(EXISTS "${_stamp}")
    file(READ "${_stamp}" _from)
    if(_from STREQUAL src)
      set(_need_copy FALSE)
    endif()
  endif()

  if(_need_copy)
    message(STATUS "Copying LIGGGHTS source from ${src}")
    file(REMOVE_RECURSE "${dst}")
    file(MAKE_DIRECTORY "${dst}")
    file(GLOB _files "${src}/*.cpp" "${src}/*.h" "${src}/Make.sh"
         "${src}/version_liggghts*.txt" "${src}/style_contact_model*.whitelist")
    file(COPY ${_files} DESTINATION "${dst}")
    # A checkout that was built in place carries generated registries: ours replace them.
    file(GLOB _old_styles "${dst}/style_*.h")
    if(_old_styles)
      file(REMOVE ${_old_styles})
    endif()

    # Contact-model registry (style_contact_model.h) as LIGGGHTS generates it.
    execute_process(COMMAND sh Make.sh models WORKING_DIRECTORY "${dst}"
                    RESULT_VARIABLE _rc OUTPUT_QUIET)
    if(NOT _rc EQUAL 0)
      message(FATAL_ERROR "LIGGGHTS 'Make.sh models' failed in ${dst}")
    endif()
    file(READ "${src}/version_liggghts.txt" _ver)
    string(STRIP "${_ver}" _ver)
    file(WRITE "${dst}/version_liggghts.h"
      "#define LIGGGHTS_VERSION \"LIGGGHTS-PUBLIC ${_ver}, with the crushable-grain package\"\n")
    file(WRITE "${_stamp}" "${src}")
  endif()

  # Changes to LIGGGHTS' own files, applied to the build copy only. Every
  # file that this package changes, or changed in an earlier version, is made
  # here from the pristine source text with the changes below (and nothing
  # else), and written only when that differs from the build copy: a build
  # tree prepared by an earlier version returns to stock where a change was
  # dropped, and unchanged files are not recompiled. A stock deck must run
  # exactly as with stock LIGGGHTS: docs/liggghts-patches.md lists each change,
  # why it is there and the test that shows stock behaviour is kept.
  foreach(_f utils.h finish.cpp lammps.cpp fix_contact_history_mesh.cpp
             comm.cpp thermo.cpp mesh_module_stress.h)
    file(READ "${src}/${_f}" _t)
    if(_f STREQUAL "utils.h")
      # GCC 12: int_to_string casts a temporary ostringstream to a reference.
      _crush_patch(_t
        "return static_cast< std::ostringstream & >(( std::ostringstream() << std::dec << a ) ).str();"
        "std::ostringstream s; s << std::dec << a; return s.str();")
    elseif(_f STREQUAL "finish.cpp")
      # GCC 12: the pointer numneigh compared with > 0 (same truth value).
      _crush_patch(_t
        "if (neighbor->lists[m]->numneigh > 0) {"
        "if (neighbor->lists[m]->numneigh != NULL) {")
    elseif(_f STREQUAL "lammps.cpp")
      # `-screen none` leaves screen NULL, but many LIGGGHTS messages (the STL
      # reader among them) print to it unchecked and crash: send them to
      # /dev/null, which is what `none` asks for.
      _crush_patch(_t
        "else if (strcmp(arg[screenflag],\"none\") == 0)\n      universe->uscreen = NULL;"
        "else if (strcmp(arg[screenflag],\"none\") == 0)\n      universe->uscreen = fopen(\"/dev/null\",\"w\");")
    elseif(_f STREQUAL "fix_contact_history_mesh.cpp")
      # Mesh walls: every step, for every mesh, FixContactHistoryMesh::
      # markAllContacts (called by fix wall/gran) cleared every page of the
      # keep flags (memset of all pages, used or not) and took two page slots
      # for every owned grain, also for the many with no triangle of that mesh
      # in their neighbour list (nneighs 0), whose slots are never read: their
      # contact history is empty after the page rebuild of a neighbour build
      # (FixContactHistoryMesh::pre_force), handleContact sees only grains in
      # a triangle's list, and cleanUpContacts, sort_contacts and n_contacts
      # loop over nneighs or npartner (both 0). Clear only the slots handed
      # out, and skip those grains (docs/studies/performance.md, "Mesh walls"). Speed
      # only: the same numbers to the last bit (docs/liggghts-patches.md).
      _crush_patch(_t
        "    keeppage_[0]->reset(true);
    intersectpage_[0]->reset(false);

    for(int i = 0; i < nlocal; i++)
    {
      const int nneighs = fix_nneighs_->get_vector_atom_int(i);
      keepflag_[i] = keeppage_[0]->get(nneighs);
      intersectflag_[i] = intersectpage_[0]->get(nneighs);
      if (!keepflag_[i] || !intersectflag_[i])
        error->one(FLERR,\"mesh contact history overflow, boost neigh_modify one\");
    }"
        "    // crushable-grain package: only the slots handed out are cleared, and
    // only grains with mesh neighbours get slots (the others' are never read)
    keeppage_[0]->reset(false);
    intersectpage_[0]->reset(false);

    for(int i = 0; i < nlocal; i++)
    {
      const int nneighs = fix_nneighs_->get_vector_atom_int(i);
      if (nneighs == 0) continue;
      keepflag_[i] = keeppage_[0]->get(nneighs);
      intersectflag_[i] = intersectpage_[0]->get(nneighs);
      if (!keepflag_[i] || !intersectflag_[i])
        error->one(FLERR,\"mesh contact history overflow, boost neigh_modify one\");
      for(int j = 0; j < nneighs; j++) keepflag_[i][j] = false;
    }")
    endif()
    # comm.cpp, thermo.cpp (lost atoms) and mesh_module_stress.h (mesh force
    # totals at the set-up of a run) were changed by earlier versions; those
    # changes altered what stock decks print and are gone: these files are
    # stock again (docs/liggghts-patches.md, "Changes that were dropped").
    _crush_write_if_changed("${dst}/${_f}" "${_t}")
  endforeach()

  # Contact-model combinations of our tangential models. `Make.sh models`
  # lists only the combinations of the stock models it finds in the build
  # copy, and pair gran / fix wall/gran instantiate exactly that list, so
  # ours are appended here (idempotent; the build copy only).
  set(_crush_gran_models
    "GRAN_MODEL(HERTZ, TANGENTIAL_INCREMENTAL, COHESION_OFF, ROLLING_OFF, SURFACE_DEFAULT)")
  file(READ "${dst}/style_contact_model.h" _gran)
  set(_gran_new "${_gran}")
  foreach(_m IN LISTS _crush_gran_models)
    string(FIND "${_gran_new}" "${_m}" _have)
    if(_have EQUAL -1)
      string(APPEND _gran_new "${_m}\n")
    endif()
  endforeach()
  _crush_write_if_changed("${dst}/style_contact_model.h" "${_gran_new}")

  # Style registries: every header (stock or ours) that declares the class.
  set(_styles
    "ANGLE_CLASS:angle_:angle" "ATOM_CLASS:atom_vec_:atom" "BODY_CLASS:body_:body"
    "BOND_CLASS:bond_:bond" "COMMAND_CLASS::command" "COMPUTE_CLASS:compute_:compute"
    "DIHEDRAL_CLASS:dihedral_:dihedral" "DUMP_CLASS:dump_:dump" "FIX_CLASS:fix_:fix"
    "IMPROPER_CLASS:improper_:improper" "INTEGRATE_CLASS::integrate" "KSPACE_CLASS::kspace"
    "MINIMIZE_CLASS:min_:minimize" "PAIR_CLASS:pair_:pair"
    "SURFACE_MODEL:surface_model_:surface_model" "NORMAL_MODEL:normal_model_:normal_model"
    "TANGENTIAL_MODEL:tangential_model_:tangential_model"
    "COHESION_MODEL:cohesion_model_:cohesion_model" "ROLLING_MODEL:rolling_model_:rolling_model"
    "READER_CLASS:reader_:reader" "REGION_CLASS:region_:region"
    "CFD_DATACOUPLING_CLASS:cfd_datacoupling_:cfd_datacoupling"
    "CFD_REGIONMODEL_CLASS:cfd_regionmodel_:cfd_regionmodel" "LB_CLASS::lb"
    "SPH_KERNEL_CLASS:sph_kernel_:sph_kernel" "MESHMODULE_CLASS:mesh_module_:mesh_module"
    "MESHMOVER_CLASS:mesh_mover_:mesh_mover")
  file(GLOB _stock_headers RELATIVE "${dst}" "${dst}/*.h")
  file(GLOB _plugin_headers RELATIVE "${plugin_dir}" CONFIGURE_DEPENDS "${plugin_dir}/*.h")
  list(SORT _stock_headers)
  list(SORT _plugin_headers)
  foreach(_entry IN LISTS _styles)
    string(REPLACE ":" ";" _parts "${_entry}")
    list(GET _parts 0 _key)
    list(GET _parts 1 _prefix)
    list(GET _parts 2 _name)
    set(_content "")
    foreach(_set stock plugin)
      if(_set STREQUAL "stock")
        set(_dir "${dst}")
        set(_list ${_stock_headers})
      else()
        set(_dir "${plugin_dir}")
        set(_list ${_plugin_headers})
      endif()
      foreach(_h IN LISTS _list)
        if(NOT _prefix STREQUAL "")
          string(FIND "${_h}" "${_prefix}" _p)
          if(NOT _p EQUAL 0)
            continue()
          endif()
        endif()
        if(_h MATCHES "^style_")
          continue()
        endif()
        file(STRINGS "${_dir}/${_h}" _hit REGEX "${_key}" LIMIT_COUNT 1)
        if(_hit)
          string(APPEND _content "#include \"${_h}\"\n")
        endif()
      endforeach()
    endforeach()
    _crush_write_if_changed("${dst}/style_${_name}.h" "${_content}")
  endforeach()
  # Registries are rebuilt when a plugin header changes (a new style appears).
  foreach(_h IN LISTS _plugin_headers)
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${plugin_dir}/${_h}")
  endforeach()
endfunction()
