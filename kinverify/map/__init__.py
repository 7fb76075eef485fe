"""The sim-to-sim contract (``kinverify map``): the order each file's simulator gives the joints
and the actuators, the index maps between every two files, and, side by side in one unit, the
values a policy depends on (default pose, PD gains, limits, armature, friction, drives and
couplings), their differences as findings. See docs/map.md.

The pipeline: :mod:`~kinverify.map.readers` (one reader per format: :mod:`~kinverify.map.urdf`,
:mod:`~kinverify.map.mjcf`, :mod:`~kinverify.map.sdf`; :mod:`~kinverify.map.table` for an actuator
table) -> :mod:`~kinverify.map.side` -> :mod:`~kinverify.map.rows` -> :mod:`~kinverify.map.compare`,
:mod:`~kinverify.map.drives`, :mod:`~kinverify.map.maps` -> :mod:`~kinverify.map.contract`
(:func:`map_files`) -> :mod:`~kinverify.map.render`."""
