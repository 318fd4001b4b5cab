# The control center and the simulated machines share one image: the same package and the
# same `ednc` commands the test suite runs natively (`ednc serve`, `ednc sim`).
FROM python:3.11-slim
WORKDIR /app
COPY pyproject.toml README.md ./
COPY volumetric volumetric
COPY protocol protocol
COPY server server
COPY machine_sim machine_sim
COPY ednc ednc
RUN pip install --no-cache-dir .
EXPOSE 8080 7878
CMD ["ednc", "serve"]
