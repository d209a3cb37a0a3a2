"""The bearing and its contact history, on top of :mod:`bearing_envelope.contact`.

- :mod:`.scene`: the scene (bearing, materials, operation, defect, load) and its checks;
- :mod:`.catalogue`: named bearings (data/bearings.yaml) with the source of every number;
- :mod:`.kinematics`: fault frequencies (BPFO, BPFI, BSF, FTF) from the geometry;
- :mod:`.loads`: the load zone (roller loads around the race);
- :mod:`.geometry`: contact grids, the gap with the defect, the Hertz estimate;
- :mod:`.fidelity`: numerical settings (grids, table nodes, tolerances) and presets;
- :mod:`.solves`: the global no-defect and local window solves with the defect;
- :mod:`.table`: the pressure table ``P(Q, x)`` built from those solves;
- :mod:`.kernels`: numba kernels of the table reading and the synthesis;
- :mod:`.acquisition`: point or anti-aliased sampling, noise;
- :mod:`.locations`: the fault locations, one object each in one table (kinematics, exposure,
  table needs, signals of the inner race, outer race and rolling element);
- :mod:`.exposure`: the loads a defect meets, before any solve;
- :mod:`.history`: the case's tables and signals from its location, :func:`~.history.simulate`;
- :mod:`.pit`: when the bottom of a pit carries load;
- :mod:`.transfer`: the structural path to a synthetic accelerometer;
- :mod:`.dynamics`: the dynamic lumped-parameter bearing (docs/dynamics.md).

Nothing here imports from the layers above (signal, diagnosis, io, study, cli).
"""
