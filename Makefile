# Convenience aliases for ./shore (which needs nothing but bash).
.PHONY: demo test bench sanitize double viewer
demo test bench sanitize double viewer:
	./shore $@
