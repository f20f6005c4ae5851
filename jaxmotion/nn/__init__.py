"""Network layers shared by the models, all pure functions over NamedTuple parameter pytrees in PyTorch's
layout: the primitives (``core``: default initialisation, Linear, LayerNorm, BatchNorm, dropout), GRU
(``recurrent``, ``lax.scan``), Transformer layers (``transformer``) and the ST-GCN recogniser (``stgcn``)."""
