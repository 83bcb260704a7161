// Reads the parameter schema from the Rust source (the single source of truth), so the TS tests
// use exactly the names, defaults and ranges the core will send over CoreClient.schema().
import type { ParamSpec } from '../../web/src/core-client/protocol';
import paramsRs from '../../wasm-core/crates/heartmesh-core/src/params.rs?raw';

const PARAMS_RS = 'wasm-core/crates/heartmesh-core/src/params.rs';

export function rustSchema(): ParamSpec[] {
  const text: string = paramsRs;
  const re =
    /ParamSpec\s*\{\s*name:\s*"([^"]+)",\s*default:\s*([^,]+),\s*min:\s*([^,]+),\s*max:\s*([^,]+),\s*log:\s*(true|false),\s*integer:\s*(true|false),\s*unit:\s*"([^"]*)",\s*help:\s*"([^"]*)"/g;
  const out: ParamSpec[] = [];
  for (const m of text.matchAll(re)) {
    out.push({
      name: m[1],
      default: Number(m[2]),
      min: Number(m[3]),
      max: Number(m[4]),
      log: m[5] === 'true',
      integer: m[6] === 'true',
      unit: m[7],
      help: m[8],
    });
  }
  if (out.length === 0) throw new Error(`no ParamSpec found in ${PARAMS_RS}`);
  return out;
}
