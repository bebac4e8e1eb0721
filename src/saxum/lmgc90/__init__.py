"""LMGC90 models: read a DATBOX folder into a saxum model or scenario
(`import_lmgc90`, `saxum import-lmgc90`), and write a saxum model as a DATBOX
(`export_lmgc90`, `saxum export-lmgc90`), and LMGC90's contact files (Vloc_Rloc.INI) as the
first step's warm start. docs/lmgc90.md is the migration guide."""

from .reader import Datbox, read_datbox
from .translate import OVERLAP_TOLERANCE, Lmgc90Import, Untranslated, import_lmgc90, translate
from .vlocrloc import VlocEntry, read_vloc_rloc, write_vloc_rloc
from .writer import export_lmgc90

__all__ = ["OVERLAP_TOLERANCE", "Datbox", "Lmgc90Import", "Untranslated", "VlocEntry",
           "export_lmgc90", "import_lmgc90", "read_datbox", "read_vloc_rloc", "translate",
           "write_vloc_rloc"]
