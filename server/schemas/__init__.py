"""Request and response models of the REST API, one module per resource
(``XCreate`` in, ``XPublic`` out; secrets only ever in ``XCreate``/``XUpdate``)."""
