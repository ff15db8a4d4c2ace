// The page's LPV off the main thread: injection, the geometry volume and propagation of
// twin.js (float64), so a 32³ grid propagating never blocks scrolling or the controls;
// a request's ``channels`` (default all) are the colour channels this worker runs.
// Messages: {id, type: "light", index, views} keeps the VPL sets of a light choice;
// {id, type: "run", ...request} answers {id, accumulated, audit, ms}. A run whose request
// differs from the last one only by more iterations continues from the last grid (the
// same operations in the same order as a run from the start).
import * as twin from "./twin.js";

const lights = [];
let cache = null;

function keyOf(request) {
  const {iterations, ...rest} = request;
  return JSON.stringify(rest);
}

/** The request's neighbourhood: 6 (as published) unless it asks for 26. */
function neighboursOf(request) {
  return request.neighbours === undefined ? 6 : request.neighbours;
}

function setsOf(request) {
  return request.views !== undefined ? request.views : lights[request.light].views;
}

function run(request) {
  const started = performance.now();
  const key = keyOf(request);
  const n = request.spec.resolution;
  const ms = {inject: 0, geometry: 0, propagate: 0};
  if (cache === null || cache.key !== key || cache.t > request.iterations) {
    const views = setsOf(request);
    let grid = null;
    for (const vpls of views) {
      const one = twin.inject(vpls, request.spec, request.corrections, request.offset,
                              request.channels);
      if (grid === null) {
        grid = one;
      } else {
        for (let i = 0; i < grid.length; i++) {
          grid[i] += one[i];
        }
      }
    }
    ms.inject = performance.now() - started;
    let geometry = null;
    if (request.geometry !== "off") {
      const begin = performance.now();
      geometry = twin.mergeGeometry(views.map(
        (vpls) => twin.injectGeometry(vpls, request.spec, request.corrections,
                                      request.geometry)));
      ms.geometry = performance.now() - begin;
    }
    const first = twin.propagateAudited(grid, n, request.corrections, 0, geometry,
                                        request.channels, neighboursOf(request));
    cache = {key, t: 0, geometry, ...first};
  }
  const begin = performance.now();
  const more = request.iterations - cache.t;
  if (more > 0) {
    const next = twin.continuePropagation(cache, n, request.corrections, more,
                                          cache.geometry, request.channels,
                                          neighboursOf(request));
    Object.assign(cache, next);
    cache.t = request.iterations;
  }
  ms.propagate = performance.now() - begin;
  ms.total = performance.now() - started;
  return {accumulated: cache.accumulated.slice(), audit: structuredClone(cache.audit), ms,
          continued: ms.inject === 0 && ms.geometry === 0};
}

self.onmessage = (event) => {
  const message = event.data;
  try {
    if (message.type === "light") {
      lights[message.index] = {views: message.views};
      self.postMessage({id: message.id});
    } else if (message.type === "run") {
      const answer = run(message.request);
      self.postMessage({id: message.id, ...answer}, [answer.accumulated.buffer]);
    }
  } catch (error) {
    self.postMessage({id: message.id, error: String(error && error.message || error)});
  }
};
