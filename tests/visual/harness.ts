// TEST-ONLY entry: the real page (bootstrap) with the synthetic core of fakeCore.ts.
import { bootstrap } from '../../web/src/app/bootstrap';
import type { CoreClient } from '../../web/src/core-client/CoreClient';
import { FakeCoreClient } from './fakeCore';

bootstrap(() => FakeCoreClient.create() as unknown as Promise<CoreClient>);
