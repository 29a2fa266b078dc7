# Convenience aliases for ./shore (which needs nothing but bash).
.PHONY: demo test bench sanitize double
demo test bench sanitize double:
	./shore $@
