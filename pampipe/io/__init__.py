"""The I/O layer: every file format pampipe reads or writes lives here, and nowhere else.

* :mod:`.yamlfile`: reading YAML files safely; :mod:`.yamlwrite`: writing them through one emitter;
* :mod:`.pam_schema`, :mod:`.experiment_schema`, :mod:`.mission_schema`: the PAM, experiment and mission
  files (docs/formats.md §2-§4) → SI objects, over the fields of :mod:`.schema_fields`;
* :mod:`.csvfile`: CSV data → SI arrays;
* :mod:`.pamfile`: a :class:`~pampipe.model.pam.Pam` → PAM file;
* :mod:`.files`: atomic writes, input protection and deterministic JSON.
* :mod:`.validated`: validated missions and experiments kept in the user's cache
  (:mod:`pampipe.runtime.cache`).

The science packages (identify, plan, gait, diagnose, synth) never import this layer; the Python
API (:mod:`pampipe.api`) and the command modules do.
"""
