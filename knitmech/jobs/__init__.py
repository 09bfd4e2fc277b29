"""The jobs the stages run on DOLFINx, in this process or under `mpirun`: one launcher
(`knitmech.jobs.launch.run_job`) and one entry point,

    mpirun -n N python -m knitmech.jobs KIND REQUEST.json FOLDER SUMMARY.json

which rank 0 ends by writing the job's JSON summary. Kinds (`launch.JOBS`): `patch` (the
patch tension test of the macro stage, `knitmech.jobs.patch`), `fabric` (a scene's part,
`knitmech.jobs.fabric`) and `sleeve` (a compression sleeve drawn over a limb, the design's
contact model, `knitmech.jobs.sleeve`); each module's `run_request(request, folder, comm) ->
dict` runs one.
"""
