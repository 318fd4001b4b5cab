"""One module per ``ednc`` sub-command; each defines ``register(app)``.

The CLI discovers the modules here, so adding a command never touches a shared file.
"""
