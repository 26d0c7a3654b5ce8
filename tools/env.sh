# Sourced by the tools: puts nvcc on PATH where the CUDA toolkit's installer left it.
if ! command -v nvcc >/dev/null 2>&1 && [ -x /usr/local/cuda/bin/nvcc ]; then
  export PATH="$PATH:/usr/local/cuda/bin"
fi
