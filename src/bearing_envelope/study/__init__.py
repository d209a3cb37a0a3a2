"""The parametric study on top of the library: validated settings, the per-case pipeline of
the workflow's jobs, tables, figures, the study-vs-model page, accuracy and trade-off studies,
provenance.

- :mod:`.schema` and :mod:`.settings`: the config's schema, its one validating loader and the
  typed settings every job receives;
- :mod:`.pipeline`: what each workflow job computes for one case;
- :mod:`.tables`, :mod:`.figures`, :mod:`.paper`: the sweep's tables, figures and paper page;
- :mod:`.accuracy`, :mod:`.tradeoff`: the measured discretisation error and the
  speed-accuracy trade;
- :mod:`.provenance`: code dependencies of the workflow scripts, job logs.
"""
