# Sourced by setup.sh, test.sh and main.sh: the LAMMPS version chosen with NCF_LAMMPS and the
# default build folder of each, so that builds against both versions live side by side.
#   NCF_LAMMPS=2025  LAMMPS 4 Feb 2025 (the default)   -> ./build
#   NCF_LAMMPS=2026  LAMMPS 4 Jul 2026                  -> ./build-lammps2026
# NCF_BUILD, when set, overrides the folder.
ncf_lammps=${NCF_LAMMPS:-2025}
case $ncf_lammps in
  2025) ncf_default_build=build ;;
  2026) ncf_default_build=build-lammps2026 ;;
  *)
    printf '[ncf] ERROR: NCF_LAMMPS=%s: choose 2025 (LAMMPS 4 Feb 2025, the default) or 2026 (LAMMPS 4 Jul 2026)\n' \
      "$ncf_lammps" >&2
    exit 1
    ;;
esac
