"""The I/O layer: every file format pampipe reads or writes lives here, and nowhere else.

* :mod:`.yamlfile`: reading YAML files safely; :mod:`.yamlwrite`: writing them through one emitter;
* :mod:`.config`: the PAM, experiment and mission schemas (docs/formats.md §1-§4) → SI objects;
* :mod:`.csvfile`: CSV data → SI arrays;
* :mod:`.pamfile`: a :class:`~pampipe.model.pam.Pam` → PAM file;
* :mod:`.files`: atomic writes, input protection and deterministic JSON.
* :mod:`.cache`: the user's on-disk cache folder; :mod:`.validated`: validated missions and experiments kept
  there.

The science packages (identify, plan, gait, diagnose, synth) never import this layer; the Python
API (:mod:`pampipe.api`) and the command modules do.
"""
