"""One module per `rustycs` command; each defines NAME and `command`."""
