# Two commands do everything on a fresh Debian/Ubuntu machine:
#   make run    install what is missing, build, show the default clay scene
#   make test   install what is missing, build, run the whole suite (validation on)

CARGO ?= cargo
# The Vulkan window-system code warns without a runtime directory; give it a private one.
ifeq ($(strip $(XDG_RUNTIME_DIR)),)
XDG_RUNTIME_DIR := /tmp/argil-runtime-$(shell id -u)
endif
export XDG_RUNTIME_DIR

.PHONY: setup build run test clean

setup:
	@bash scripts/setup.sh
	@mkdir -p -m 700 "$(XDG_RUNTIME_DIR)"

build: setup
	$(CARGO) build --release --locked

# A window when a display exists, otherwise a PNG.
run: build
	@if [ -n "$$DISPLAY$$WAYLAND_DISPLAY" ]; then \
		target/release/argil view; \
	else \
		echo "argil: no display; rendering the default scene to clay.png"; \
		target/release/argil render --out clay.png --overwrite && echo "argil: wrote $(CURDIR)/clay.png"; \
	fi

# Release build, shared with `make run`; the tests turn the validation layer on themselves.
# Then every BRDF and shading function checked on the GPU against its f64 twin, with 2^20
# tuples each.
# The tests keep argil's disk cache (builtin maps, tables, pipelines) inside target/, away
# from the user's.
test: setup
	ARGIL_CACHE_DIR=$(CURDIR)/target/argil-cache $(CARGO) test --release --locked
	ARGIL_CACHE_DIR=$(CURDIR)/target/argil-cache target/release/argil --validation verify

# Every BRDF model and term, normal-mapping and shading function on the GPU against its f64
# twin: accuracy, positivity or unit length, reciprocity, energy, stress inputs (also the
# last step of `make test`).
verify: build
	ARGIL_CACHE_DIR=$(CURDIR)/target/argil-cache target/release/argil --validation verify

clean:
	$(CARGO) clean
