# Copies LIGGGHTS' src/ into the build tree, applies the fixes that GCC 12
# needs there, and writes the style_*.h registries (what `Make.sh style` does)
# so that they list the stock styles and ours from src_liggghts_plugin/.

# Replace `from` by `to` in `file`; fail loudly if the text is not there, so
# a LIGGGHTS version we were not written for is noticed.
function(_crush_patch file from to)
  file(READ "${file}" _text)
  string(FIND "${_text}" "${to}" _done)
  if(NOT _done EQUAL -1)
    return()  # already patched (`to` may contain `from`)
  endif()
  string(FIND "${_text}" "${from}" _pos)
  if(_pos EQUAL -1)
    message(FATAL_ERROR "Cannot patch ${file}: text not found: ${from}")
  endif()
  string(REPLACE "${from}" "${to}" _text "${_text}")
  file(WRITE "${file}" "${_text}")
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

  # Fixes applied in the build tree only (idempotent: a patched file is left alone).
  # GCC 12: utils.h casts a temporary ostringstream to a reference, and
  # finish.cpp compares the pointer numneigh with > 0.
  _crush_patch("${dst}/utils.h"
    "return static_cast< std::ostringstream & >(( std::ostringstream() << std::dec << a ) ).str();"
    "std::ostringstream s; s << std::dec << a; return s.str();")
  _crush_patch("${dst}/finish.cpp"
    "if (neighbor->lists[m]->numneigh > 0) {"
    "if (neighbor->lists[m]->numneigh != NULL) {")
  # `-screen none` leaves screen NULL, but many LIGGGHTS messages (the STL
  # reader among them) print to it unchecked and crash: send them to /dev/null.
  _crush_patch("${dst}/lammps.cpp"
    "else if (strcmp(arg[screenflag],\"none\") == 0)\n      universe->uscreen = NULL;"
    "else if (strcmp(arg[screenflag],\"none\") == 0)\n      universe->uscreen = fopen(\"/dev/null\",\"w\");")

  # Lost atoms. LIGGGHTS 3.8's Comm::exchange (every re-neighbouring) resets
  # atom->natoms to the current count, so atom->natoms is no bookkeeping:
  # a grain that leaves the box through a fixed boundary is dropped there and
  # the total follows it. Stock LAMMPS keeps atom->natoms as the bookkept
  # total (read_data, create_atoms, delete_atoms, fix insert, fix
  # crush/particle update it): do the same.
  _crush_patch("${dst}/comm.cpp"
    "  bigint tmp = atom->nlocal;\n  MPI_Allreduce(&tmp,&atom->natoms,1,MPI_LMP_BIGINT,MPI_SUM,world);\n\n  if (atom->firstgroupname) atom->first_reorder();"
    "  // atom->natoms is the bookkept total: not reset to the current count here,\n  // so that Thermo::lost_check sees atoms lost on the way (crushable-grain package)\n\n  if (atom->firstgroupname) atom->first_reorder();")
  # Thermo::lost_check then compares the current count with the bookkept
  # total (stock: with the count at the previous thermo output, which misses
  # a loss in an interval where fix crush/particle created more atoms, and
  # reports the atoms that fix deletes on purpose with d_frag_min).
  # (Build trees prepared before carry an earlier version of this patch.)
  set(_lost_earlier "if(ntotal < last_natoms && ntotal != atom->natoms)\n    lost = true;")
  file(READ "${dst}/thermo.cpp" _thermo)
  string(FIND "${_thermo}" "${_lost_earlier}" _earlier)
  if(_earlier EQUAL -1)
    set(_lost_earlier "if(ntotal < last_natoms)\n    lost = true;")
  endif()
  _crush_patch("${dst}/thermo.cpp" "${_lost_earlier}" "if(ntotal != atom->natoms)\n    lost = true;")

  # mesh/surface/stress zeroes its total force in pre_force and sums it over
  # the ranks in final_integrate, but not around the set-up of a run, where
  # fix wall/gran adds the set-up forces on top of the previous total: the
  # first thermo row of every run (and anything evaluated at setup) read
  # about twice the force. Reset the totals at setup as at every step, so
  # that at setup the last summed total (that of the previous step) is read.
  _crush_patch("${dst}/mesh_module_stress.h"
    "virtual void setup(int vflag) {}"
    "virtual void setup(int vflag) {}\n        virtual void setup_pre_force(int vflag) { pre_force(vflag); }")

  # Mesh walls: every step, for every mesh, FixContactHistoryMesh::markAllContacts
  # (called by fix wall/gran) cleared every page of the keep flags (memset of
  # all pages, used or not) and took two page slots for every owned grain,
  # also for the many with no triangle of that mesh in their neighbour list
  # (nneighs 0), whose slots are never read: their contact history is empty
  # after the page rebuild of a neighbour build (FixContactHistoryMesh::
  # pre_force), handleContact sees only grains in a triangle's list, and
  # cleanUpContacts, sort_contacts and n_contacts loop over nneighs or npartner
  # (both 0). Clear only the slots handed out, and skip those grains
  # (docs/performance.md, "Mesh walls").
  _crush_patch("${dst}/fix_contact_history_mesh.cpp"
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
