"""Each paper's home: its table rows (how a row trains and what it generates with), its smoke / cpu / paper sizes
and its table-specific registries. The only layer that knows both a trainer (:mod:`jaxmotion.train`) and a
pipeline (:mod:`jaxmotion.pipelines`); experiments build on it.

* :mod:`jaxmotion.recipes.actor`, :mod:`~jaxmotion.recipes.a2m`, :mod:`~jaxmotion.recipes.odmo`,
  :mod:`~jaxmotion.recipes.actformer`: a recipe per method (``fit`` trains, ``generator`` turns what it trained into
  the method's :class:`~jaxmotion.pipelines.artefacts.Generator`) and the profiles' trainings;
* :mod:`jaxmotion.recipes.evaluators`: the papers' evaluators on the embedded data, per profile;
* :mod:`jaxmotion.recipes.tables`: the paper datasets' tables per profile and the runner that trains rows, writes
  their generators beside their checkpoints and scores them together.
"""
