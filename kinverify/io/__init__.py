"""Reading and writing files: the output plan of a run (:mod:`kinverify.io.plan`) and the atomic
writer (:mod:`kinverify.io.write`)."""
