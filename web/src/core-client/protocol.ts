/**
 * The typed message protocol between the main thread (CoreClient) and the reconstruction worker.
 *
 * Every message is a discriminated union on `type`; every run-scoped message carries its `runId`
 * so that stale frames of a cancelled run can be dropped. Bulk data travel as flat typed arrays in
 * millimetres, transferred (never copied) between threads; small reports are plain objects whose
 * field names follow the Rust structs (snake_case) they are serialised from.
 */

// The protocol is split by responsibility; this module re-exports all of it, so every import of
// './protocol' keeps working and new code can import from here too.
export * from './protocolOptions';
export * from './protocolErrors';
export * from './protocolResults';
export * from './protocolAnatomical';
export * from './protocolHex';
export * from './protocolLab';
export * from './protocolMessages';
export * from './protocolHelpers';
