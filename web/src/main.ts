console.log("heartmesh");
