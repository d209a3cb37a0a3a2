"""The parametric study on top of the library: validated settings, the per-case pipeline of
the workflow's jobs, tables, figures, the study-vs-model page, accuracy and trade-off studies,
provenance.

- :mod:`.config_read` (strict YAML, merging files), :mod:`.schema` (the schema, its defaults,
  validation), :mod:`.sections` (the typed sections), :mod:`.case_id` (case names),
  :mod:`.job_transport` (typed values handed to jobs) and :mod:`.settings` (the one loader and
  the :class:`~.settings.Settings` every job's values come from);
- :mod:`.pipeline`: what each workflow job computes for one case;
- :mod:`.tables`, :mod:`.figures`, :mod:`.paper`: the sweep's tables, figures and paper page;
- :mod:`.accuracy`, :mod:`.tradeoff`: the measured discretisation error and the
  speed-accuracy trade;
- :mod:`.provenance`: code dependencies of the workflow scripts, job logs.
"""
